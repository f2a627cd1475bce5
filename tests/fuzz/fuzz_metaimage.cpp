// libFuzzer target: the MetaImage .mhd/.mha header parser (parse_metaimage_header,
// metaimage.cpp) on any text. The input is also written as the header file
// (fuzz_scratch.h) so that LOCAL data passes the size checks. A FormatError is the
// expected answer to bad input; anything else is a bug.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_scratch.h"
#include "read/text_formats.h"
#include "vdbmesh/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = vdbmesh::fuzz::write_header(data, size, "header.mhd");
    try {
        (void)vdbmesh::detail::parse_metaimage_header(std::string_view(reinterpret_cast<const char*>(data), size), path);
    } catch (const vdbmesh::Error&) {
    }
    return 0;
}
