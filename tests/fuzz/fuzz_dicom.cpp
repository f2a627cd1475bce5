// libFuzzer target: the DICOM tag parser of one slice file (parse_dicom_slice on a buffer,
// dicom_parse.cpp; GDCM walks the data set). "Not DICOM" (no value) and a FormatError are
// the expected answers to bad input; anything else is a bug. GDCM itself is not
// instrumented: coverage guides only through our code, allocations are still checked.

#include <cstddef>
#include <cstdint>

#include "read/dicom_parse.h"
#include "vdbmesh/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        if (const auto slice = vdbmesh::detail::parse_dicom_slice(data, size, "fuzz.dcm"))
            (void)slice->sample_type(), (void)slice->frame_bytes();
    } catch (const vdbmesh::Error&) {
    }
    return 0;
}
