// A scan read by region (open_scan_regions): the description, the nodes and every voxel inside
// each box read as convert_to_grid() gives them, for boxes read in z order (bricks), out of it,
// and from several threads.

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "grid_test_util.h"
#include "region_test_util.h"
#include "shared_scan.h"
#include "test_data.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/scan_regions.h"

namespace vdbmesh {
namespace {

using test::expect_same_inside;
using test::expect_same_nodes;
using test::kEverything;

/// The bricks of @a nodes_per_brick^3 nodes over @a dims voxels, each widened by @a halo, z-major.
std::vector<IndexBox> bricks(const std::array<int, 3>& dims, int nodes_per_brick, int halo) {
    const int size = nodes_per_brick * kNodeVoxels;
    std::vector<IndexBox> boxes;
    for (int z = 0; z < dims[2]; z += size)
        for (int y = 0; y < dims[1]; y += size)
            for (int x = 0; x < dims[0]; x += size) boxes.push_back({{x - halo, y - halo, z - halo}, {x + size + halo, y + size + halo, z + size + halo}});
    return boxes;
}

void expect_same_description(const openvdb::FloatGrid& whole, const openvdb::FloatGrid& description) {
    EXPECT_EQ(description.background(), whole.background());
    EXPECT_EQ(description.transform(), whole.transform());
    EXPECT_EQ(description.str(), whole.str());  // name, class, every metadata value
    EXPECT_EQ(description.tree().leafCount(), 0u);
}

/// The scan source's active leaves in @a box (row by row from its kept rows) against those of
/// its whole conversion held in memory (the default, which reads the region: LeafMasksTest).
void expect_same_active_leaves(const openvdb::FloatGrid::Ptr& whole, const GridRegionSource& source, const IndexBox& box) {
    const std::vector<LeafMask> expected = grid_regions_in_memory(whole)->active_leaves(box);
    const std::vector<LeafMask> actual = source.active_leaves(box);
    ASSERT_EQ(actual.size(), expected.size());
    for (std::size_t i = 0; i < actual.size(); ++i) {
        EXPECT_EQ(actual[i].origin, expected[i].origin) << "leaf " << i;
        EXPECT_EQ(actual[i].on, expected[i].on) << "leaf " << i;
    }
}

/// The scan @a name by region against its whole conversion: description, nodes, then @a boxes
/// in order, then the first again (back in z: the scan is reopened), then all from two threads.
void expect_regions_equal_the_whole(const std::string& name, const std::vector<IndexBox>& boxes) {
    const test::SharedScan& scan = test::shared_scan(name);
    OpenSlices open;
    ASSERT_NO_FATAL_FAILURE(test::open_shared_scan(scan, open));
    if (!open) return;
    const openvdb::FloatGrid::Ptr whole = convert_to_grid(*open(), test::shared_scan_options(scan));
    const auto source = open_scan_regions(open, test::shared_scan_options(scan));
    expect_same_description(*whole, *source->description());
    expect_same_nodes(source->nodes(), test::nodes_counted(*whole));
    for (const IndexBox& box : boxes) {
        const auto part = source->read(box);
        expect_same_inside(*whole, *part, box);
        EXPECT_GT(source->estimated_bytes(box), 0u);
    }
    expect_same_inside(*whole, *source->read(boxes.front()), boxes.front());
    expect_same_active_leaves(whole, *source, boxes.front());
    expect_same_active_leaves(whole, *source, kEverything);
    std::vector<std::shared_ptr<openvdb::FloatGrid>> parts(boxes.size());
    tbb::parallel_for(std::size_t{0}, boxes.size(), [&](std::size_t i) { parts[i] = source->read(boxes[i]); });
    for (std::size_t i = 0; i < boxes.size(); ++i) expect_same_inside(*whole, *parts[i], boxes[i]);
}

TEST(ScanRegionsTest, CTheadByBricksOfOneNodeEqualsItsWholeConversion) {
    // Halo 1 (the mesher's), halo 9 (more than a leaf: boxes reach two rows into the next layer).
    std::vector<IndexBox> boxes = bricks({256, 256, 113}, 1, 1);
    for (const IndexBox& box : bricks({256, 256, 113}, 1, 9)) boxes.push_back(box);
    boxes.push_back(IndexBox{{30, 40, 50}, {31, 41, 51}});  // one voxel, back in z
    boxes.push_back(kEverything);
    expect_regions_equal_the_whole("CThead", boxes);
}

TEST(ScanRegionsTest, BunnyCtByBricksOfTwoNodesEqualsItsWholeConversion) {
    // Two bricks of each z-layer (the corners in x and y): each layer is one band.
    std::vector<IndexBox> boxes;
    for (const IndexBox& box : bricks({512, 512, 361}, 2, 1))
        if (box.min[0] == box.min[1]) boxes.push_back(box);
    expect_regions_equal_the_whole("BunnyCt", boxes);
}

TEST(ScanRegionsTest, ASmallRawScanByBoxesAndABoxOutsideIt) {
    test::ScratchDir dir;
    const test::DenseVolume volume = test::make_volume({20, 30, 40}, [](int x, int y, int z) { return float((x * y + z) % 7); });
    const auto path = dir / "small.raw";
    test::write_and_open(volume, path);
    ConvertOptions options;
    options.iso = 3.5;
    OpenSlices open = [&] { return std::unique_ptr<SliceReader>(test::write_and_open(volume, path)); };
    const openvdb::FloatGrid::Ptr whole = convert_to_grid(*open(), options);
    const auto source = open_scan_regions(open, options);
    const auto far = source->read(IndexBox{{0, 0, 500}, {10, 10, 510}});
    EXPECT_EQ(far->tree().leafCount(), 0u);
    EXPECT_EQ(far->background(), whole->background());
    for (const IndexBox& box : {IndexBox{{-3, -3, -3}, {25, 35, 17}}, IndexBox{{5, 5, 16}, {12, 40, 45}}, kEverything}) {
        expect_same_inside(*whole, *source->read(box), box);
        expect_same_active_leaves(whole, *source, box);
    }
}

TEST(ScanRegionsTest, ColumnsOfASmallScanEqualTheWholeForEveryBand) {
    // Columns narrower than the scan convert only their part of each slice: a ball cut by the
    // scan's x = 0 and y = max faces (the virtual ring), a thin wall, and noise cross the parts'
    // edges. Columns 16 and 24 voxels wide with rings of 8, read bottom to top, at bands whose
    // halos are one and two leaves (at band 8 a halo of one leaf changes voxels in the boxes:
    // the ball's inside cut by a part's edge).
    test::ScratchDir dir;
    const test::DenseVolume volume = test::make_volume({70, 61, 43}, [](int x, int y, int z) {
        const float ball = 20.0f - std::sqrt(float(x * x + (y - 58) * (y - 58) + (z - 20) * (z - 20)));
        const float wall = std::abs(x - 41) < 1 ? 5.0f : -5.0f;
        const float noise = (x > 50 && z < 30) ? float((x * y + z) % 7) - 3.0f : -5.0f;
        return std::max({ball, wall, noise});
    });
    const auto path = dir / "small.raw";
    test::write_and_open(volume, path);
    OpenSlices open = [&] { return std::unique_ptr<SliceReader>(test::write_and_open(volume, path)); };
    for (const int band : {1, 3, 8}) {
        SCOPED_TRACE("band " + std::to_string(band));
        ConvertOptions options;
        options.iso = 0.5;
        options.band = band;
        const openvdb::FloatGrid::Ptr whole = convert_to_grid(*open(), options);
        const auto source = open_scan_regions(open, options);
        for (const int width : {16, 24})
            for (int y = -8; y < 70; y += width)
                for (int x = -8; x < 78; x += width)
                    for (int z = -16; z < 60; z += 16) {
                        const IndexBox box{{x - 8, y - 8, z}, {x + width + 8, y + width + 8, z + 16}};
                        expect_same_inside(*whole, *source->read(box), box);
                    }
    }
}

}  // namespace
}  // namespace vdbmesh
