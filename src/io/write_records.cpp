// write_records() (mesh_io_detail.h): a whole mesh's records formatted in parallel, written in
// order. Formatting (the decimal digits of ASCII, the byte-by-byte appends of binary) was the
// serial tail of every `mesh` run: about 0.5 s of one core for the bunny tiled 2 x 2 x 2 (perf).

#include <tbb/parallel_for.h>

#include <algorithm>

#include "io/mesh_io_detail.h"

namespace vdbmesh::detail {

void write_records(std::ostream& out, std::size_t count, const std::function<void(OutputBuffer&, std::size_t)>& write) {
    // A batch holds at most kChunks x kChunkRecords formatted records (a few MB), whatever the mesh.
    constexpr std::size_t kChunkRecords = std::size_t(1) << 14, kChunks = 16;
    std::vector<std::string> chunks(kChunks);
    for (std::size_t batch = 0; batch < count; batch += kChunks * kChunkRecords) {
        const std::size_t end = std::min(count, batch + kChunks * kChunkRecords);
        const std::size_t used = (end - batch + kChunkRecords - 1) / kChunkRecords;
        tbb::parallel_for(std::size_t{0}, used, [&](std::size_t c) {
            chunks[c].clear();
            OutputBuffer buffer(chunks[c]);
            const std::size_t first = batch + c * kChunkRecords;
            for (std::size_t r = first; r < std::min(end, first + kChunkRecords); ++r) write(buffer, r);
        });
        for (std::size_t c = 0; c < used; ++c) out.write(chunks[c].data(), std::streamsize(chunks[c].size()));
    }
}

}  // namespace vdbmesh::detail
