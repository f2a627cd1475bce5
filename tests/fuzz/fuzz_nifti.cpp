// libFuzzer target: the 348-byte NIfTI-1 / Analyze 7.5 header parser (nifti_header.cpp).
// A FormatError is the expected answer to bad input; anything else is a bug.

#include <cstddef>
#include <cstdint>

#include "read/nifti_header.h"
#include "vdbmesh/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)vdbmesh::detail::parse_nifti_analyze_header(data, size, "fuzz.nii");
    } catch (const vdbmesh::Error&) {
    }
    return 0;
}
