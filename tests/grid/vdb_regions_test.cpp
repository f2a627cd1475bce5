// A .vdb read by region (open_vdb_regions): every voxel inside a box as in the whole grid, the
// nodes from the topology alone, reads from several threads, and a corrupt leaf buffer a
// FormatError naming the file, not a crash.

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <limits>
#include <map>
#include <tuple>
#include <vector>

#include "region_test_util.h"
#include "shared_scan.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"

namespace vdbmesh {
namespace {

using test::expect_same_inside;
using test::expect_same_nodes;
using test::kEverything;
using test::nodes_counted;
using test::ScratchDir;

/// Boxes of several kinds over a grid of @a dims voxels: whole nodes with a halo, a box
/// through the middle of leaves, one voxel, one outside every value, everything.
std::vector<IndexBox> boxes_over(const std::array<int, 3>& dims) {
    return {IndexBox{{-1, -1, -1}, {129, 129, 129}},
            IndexBox{{127, 0, 3}, {dims[0], 131, dims[2] / 2 + 5}},
            IndexBox{{dims[0] / 2, dims[1] / 2, dims[2] / 2}, {dims[0] / 2 + 1, dims[1] / 2 + 1, dims[2] / 2 + 1}},
            IndexBox{{5000, 5000, 5000}, {5010, 5010, 5010}},
            kEverything};
}

/// A grid with a value of every kind: voxels, an active and an inactive tile at each internal
/// level, a node that holds only inactive values, negative coordinates.
openvdb::FloatGrid::Ptr grid_of_every_kind() {
    auto grid = openvdb::FloatGrid::create(-2.0f);
    auto& tree = grid->tree();
    for (int i = 0; i < 300; ++i) tree.setValue(openvdb::Coord(i, (i * 7) % 200 - 60, (i * 13) % 170), float(i));
    tree.addTile(1, openvdb::Coord(256, 8, 16), 5.0f, true);
    tree.addTile(1, openvdb::Coord(264, 8, 16), 6.0f, false);
    tree.addTile(2, openvdb::Coord(-128, 0, 128), 7.0f, true);
    tree.addTile(2, openvdb::Coord(-256, 0, 128), 8.0f, false);
    tree.setValueOff(openvdb::Coord(600, 600, 600), 9.0f);
    return grid;
}

TEST(VdbRegionsTest, TilesAndVoxelsOfEveryLevelArriveInsideEachBox) {
    ScratchDir dir;
    const auto grid = grid_of_every_kind();
    write_vdb(*grid, dir / "kinds.vdb");
    const auto source = open_vdb_regions(dir / "kinds.vdb");
    EXPECT_EQ(source->description()->tree().activeVoxelCount(), 0u);
    EXPECT_EQ(source->description()->background(), -2.0f);
    expect_same_nodes(source->nodes(), nodes_counted(*grid));
    for (const IndexBox& box : boxes_over({300, 200, 170})) {
        const auto part = source->read(box);
        expect_same_inside(*grid, *part, box);
        EXPECT_GE(source->estimated_bytes(box), part->tree().memUsage());
    }
    // A node far from the box is not read.
    EXPECT_EQ(source->read(IndexBox{{0, 0, 0}, {8, 8, 8}})->tree().getValue(openvdb::Coord(600, 600, 600)), -2.0f);
}

TEST(VdbRegionsTest, EveryVoxelInsideEachBoxOfCTheadIsTheWholeGrids) {
    openvdb::FloatGrid::Ptr grid;
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(test::shared_scan("CThead"), grid));
    if (!grid) return;
    ScratchDir dir;
    write_vdb(*grid, dir / "cthead.vdb");
    const auto source = open_vdb_regions(dir / "cthead.vdb");
    expect_same_nodes(source->nodes(), nodes_counted(*grid));
    const std::vector<IndexBox> boxes = boxes_over({256, 256, 113});
    std::vector<std::shared_ptr<openvdb::FloatGrid>> parts(boxes.size());
    // From several threads at once: each read forks its own child.
    tbb::parallel_for(std::size_t{0}, boxes.size(), [&](std::size_t i) { parts[i] = source->read(boxes[i]); });
    for (std::size_t i = 0; i < boxes.size(); ++i) expect_same_inside(*grid, *parts[i], boxes[i]);
    EXPECT_EQ(read_vdb(dir / "cthead.vdb")->activeVoxelCount(), grid->activeVoxelCount());
}

/// nucleon.dat converted at iso 80, as `vdbmesh convert` writes it, with the byte that makes
/// OpenVDB's reader corrupt its heap while decoding a leaf buffer (see untrusted_vdb_test.cpp).
TEST(VdbRegionsTest, AReaderCrashOnALeafBufferIsAFormatErrorNamingTheFile) {
    VDBMESH_SHARED_DATA(scan, "openqvis_nucleon_sim/nucleon.dat");
    ScratchDir dir;
    ConvertOptions options;
    options.iso = 80;
    const auto path = dir / "nucleon.vdb";
    write_vdb(*convert_to_grid(*open_volume(scan), options), path);
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(4270);
    file.put(static_cast<char>(0xDB));
    file.close();
    try {
        open_vdb_regions(path)->read(kEverything);
        ADD_FAILURE() << "a corrupt file was read";
    } catch (const FormatError& e) {
        EXPECT_EQ(std::string(e.what()).find(path.string()), 0u) << e.what();
    }
}

TEST(VdbRegionsTest, AFileWithoutAFloatGridIsAFormatError) {
    ScratchDir dir;
    const auto path = dir / "ints.vdb";
    openvdb::initialize();
    openvdb::io::File(path.string()).write({openvdb::Int32Grid::create(3)});
    try {
        open_vdb_regions(path);
        ADD_FAILURE() << "a file without a float grid was opened";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("a float grid"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace vdbmesh
