// Times the streaming conversion of the bunny CT (shared data, DESIGN.md section 3) against
// the dense route OpenVDB offers: read the whole volume into memory, then
// openvdb::tools::copyFromDense. Both in this process, one run each; not a test.
//
// Usage: convert_bench [ISO]   (default 1200.5; the data folder is found as the tests find it)

#include <openvdb/tools/Dense.h>

#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "test_data.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/read.h"

namespace {

using Clock = std::chrono::steady_clock;

/// Wall time and process CPU time (all threads): on a shared machine CPU time is the steadier.
struct Stopwatch {
    Clock::time_point wall = Clock::now();
    std::clock_t cpu = std::clock();
    std::string text() const {
        char line[64];
        std::snprintf(line, sizeof line, "%6.2f s wall %6.2f s cpu", std::chrono::duration<double>(Clock::now() - wall).count(),
                      static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC);
        return line;
    }
};

void print_grid(const char* label, const openvdb::FloatGrid& grid, const Stopwatch& watch) {
    std::printf("%-30s %s  %10llu active voxels %7llu leaves %7.1f MB in memory\n", label, watch.text().c_str(),
                static_cast<unsigned long long>(grid.activeVoxelCount()),
                static_cast<unsigned long long>(grid.tree().leafCount()), grid.memUsage() / 1e6);
}

}  // namespace

int main(int argc, char** argv) {
    const double iso = argc > 1 ? std::atof(argv[1]) : 1200.5;
    const auto folder = vdbmesh::test::shared_data_dir() / "raw_stanford_ct_bunny";
    const auto part1 = folder / "bunny_ct_512x512x361_uint16be.part1of2.raw.gz";
    if (!std::filesystem::exists(part1)) {
        std::fprintf(stderr, "convert_bench: %s not found\n", part1.c_str());
        return 1;
    }
    vdbmesh::ReadOptions read;
    read.raw_dims = std::array<std::int64_t, 3>{512, 512, 361};
    read.raw_type = vdbmesh::SampleType::i16;
    read.raw_byte_order = vdbmesh::ByteOrder::big;
    read.raw_spacing = {0.337891, 0.337891, 0.5};
    read.raw_more_files = {folder / "bunny_ct_512x512x361_uint16be.part2of2.raw.gz"};
    vdbmesh::test::ScratchDir scratch;
    std::printf("bunny CT 512x512x361, iso %g\n", iso);

    // Streaming: slabs -> sparse grid -> .vdb
    Stopwatch watch;
    auto reader = vdbmesh::open_volume(part1, read);
    vdbmesh::ConvertOptions options;
    options.iso = iso;
    const auto sparse = vdbmesh::convert_to_grid(*reader, options);
    print_grid("stream + convert_to_grid", *sparse, watch);
    watch = Stopwatch();
    vdbmesh::write_vdb(*sparse, scratch / "sparse.vdb");
    std::printf("%-30s %s  %10.1f MB on disk\n", "write_vdb", watch.text().c_str(),
                std::filesystem::file_size(scratch / "sparse.vdb") / 1e6);

    // Dense: whole volume in memory -> copyFromDense (every sample active but those equal to
    // the background, here the padding value -2000, as tolerance 0 keeps everything else).
    watch = Stopwatch();
    auto dense_reader = vdbmesh::open_volume(part1, read);
    const auto& dims = dense_reader->header().dims;
    std::vector<float> volume(static_cast<std::size_t>(dense_reader->header().voxel_count()));
    dense_reader->read_slices(dims[2], volume.data());
    std::printf("%-30s %s  %10.1f MB of floats\n", "read whole volume", watch.text().c_str(),
                volume.size() * sizeof(float) / 1e6);
    watch = Stopwatch();
    const openvdb::CoordBBox box(openvdb::Coord(0), openvdb::Coord(static_cast<int>(dims[0] - 1),
                                                                   static_cast<int>(dims[1] - 1),
                                                                   static_cast<int>(dims[2] - 1)));
    openvdb::tools::Dense<float, openvdb::tools::LayoutXYZ> dense(box, volume.data());  // x fastest, as read
    auto copied = openvdb::FloatGrid::create(-2000.0f);
    openvdb::tools::copyFromDense(dense, copied->tree(), 0.0f);
    print_grid("copyFromDense (tolerance 0)", *copied, watch);
    watch = Stopwatch();
    vdbmesh::write_vdb(*copied, scratch / "dense.vdb");
    std::printf("%-30s %s  %10.1f MB on disk\n", "write_vdb (dense route)", watch.text().c_str(),
                std::filesystem::file_size(scratch / "dense.vdb") / 1e6);
    return 0;
}
