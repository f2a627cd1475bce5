// libFuzzer target: the NRRD header parser (parse_nrrd_header in nrrd.cpp) on any text.
// The input is also written as the header file (fuzz_scratch.h) so that attached data
// passes the size checks. "line skip" is answered without reading: one byte per line, as
// if the lines were empty. A FormatError is the expected answer to bad input; anything
// else is a bug.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_scratch.h"
#include "read/text_formats.h"
#include "vdbmesh/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = vdbmesh::fuzz::write_header(data, size, "header.nrrd");
    const auto empty_lines = [](const std::filesystem::path&, std::uint64_t, std::int64_t lines) {
        return static_cast<std::uint64_t>(lines);
    };
    try {
        (void)vdbmesh::detail::parse_nrrd_header(std::string_view(reinterpret_cast<const char*>(data), size), path,
                                                 empty_lines);
    } catch (const vdbmesh::Error&) {
    }
    return 0;
}
