// libFuzzer target: the OBJ mesh reader (read_obj in read_obj.cpp) on bytes in memory,
// as read_mesh() calls it after reading the file. A FormatError is the expected answer to
// bad input; anything else is a bug.

#include <cstddef>
#include <cstdint>

#include "io/mesh_io_detail.h"
#include "vdbmesh/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const vdbmesh::detail::Bytes bytes(data, data + size);
    try {
        (void)vdbmesh::detail::read_obj("fuzz.obj", bytes);
    } catch (const vdbmesh::Error&) {
    }
    return 0;
}
