// libFuzzer target: reading a .vdb from outside (read_vdb: the size and header checks, the
// child process that reads the file first, then OpenVDB's reader in this process). A
// FormatError is the expected answer to a bad file; any other exception, a hang or a crash of
// this process is a bug. A crash of the child is not: it is what the child is for.

#include <cstddef>
#include <cstdint>

#include "fuzz_scratch.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = vdbmesh::fuzz::write_header(data, size, "input.vdb");
    try {
        (void)vdbmesh::read_vdb(path);
    } catch (const vdbmesh::Error&) {
    }
    return 0;
}
