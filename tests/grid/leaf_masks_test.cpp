// GridRegionSource::active_leaves(): a .vdb's source answers from its topology, the default
// by reading the region; both give every leaf's active voxels inside the box as the voxels
// themselves say, in z-major order, active tiles not listed.

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <tuple>
#include <vector>

#include "region_test_util.h"
#include "test_data.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"

namespace vdbmesh {
namespace {

using test::kEverything;
using test::ScratchDir;

/// Voxels scattered over several leaves and nodes (negative coordinates too), a full leaf,
/// and active and inactive tiles, which are not listed.
openvdb::FloatGrid::Ptr grid_with_tiles() {
    auto grid = openvdb::FloatGrid::create(0.0f);
    auto& tree = grid->tree();
    for (int i = 0; i < 400; ++i) tree.setValue(openvdb::Coord((i * 5) % 150 - 20, (i * 7) % 90, (i * 13) % 170 - 40), 1.0f);
    for (int x = 0; x < 8; ++x)
        for (int y = 0; y < 8; ++y)
            for (int z = 0; z < 8; ++z) tree.setValue(openvdb::Coord(200 + x, 16 + y, 8 + z), 2.0f);
    tree.setValueOff(openvdb::Coord(3, 3, 3), 4.0f);  // an inactive voxel in a leaf with active ones
    tree.addTile(1, openvdb::Coord(256, 8, 16), 5.0f, true);
    tree.addTile(2, openvdb::Coord(-128, 0, 128), 7.0f, true);
    return grid;
}

using Key = std::tuple<std::int32_t, std::int32_t, std::int32_t>;  // z, y, x: z-major order

/// The masks counted voxel by voxel: each active voxel (not tile) inside @a box sets its bit.
std::vector<LeafMask> masks_counted(const openvdb::FloatGrid& grid, const IndexBox& box) {
    std::map<Key, LeafMask> leaves;
    for (auto v = grid.tree().cbeginValueOn(); v; ++v) {
        if (!v.isVoxelValue()) continue;
        const openvdb::Coord c = v.getCoord();
        bool inside = true;
        for (int a = 0; a < 3; ++a) inside = inside && c[a] >= box.min[a] && c[a] < box.max[a];
        if (!inside) continue;
        const openvdb::Coord origin = c & ~7;
        LeafMask& mask = leaves[Key{origin.z(), origin.y(), origin.x()}];
        mask.origin = {origin.x(), origin.y(), origin.z()};
        const int x = c.x() - origin.x(), y = c.y() - origin.y(), z = c.z() - origin.z();
        mask.on[x] |= std::uint64_t{1} << (y * 8 + z);
    }
    std::vector<LeafMask> masks;
    for (const auto& [key, mask] : leaves) masks.push_back(mask);
    return masks;
}

void expect_same_masks(const std::vector<LeafMask>& actual, const std::vector<LeafMask>& expected) {
    ASSERT_EQ(actual.size(), expected.size());
    for (std::size_t i = 0; i < actual.size(); ++i) {
        EXPECT_EQ(actual[i].origin, expected[i].origin) << "leaf " << i;
        EXPECT_EQ(actual[i].on, expected[i].on) << "leaf " << i;
    }
}

TEST(LeafMasksTest, TheVdbTopologyAndTheRegionsReadGiveTheVoxelsMasks) {
    ScratchDir dir;
    const auto grid = grid_with_tiles();
    write_vdb(*grid, dir / "tiles.vdb");
    const auto from_file = open_vdb_regions(dir / "tiles.vdb");
    const auto in_memory = grid_regions_in_memory(grid);  // the default: reads the region
    // Everything; whole nodes; a box through the middle of leaves; one voxel; nothing.
    for (const IndexBox& box : {kEverything, IndexBox{{0, 0, 0}, {128, 128, 128}}, IndexBox{{-13, 3, -5}, {97, 61, 130}},
                                IndexBox{{203, 19, 12}, {204, 20, 13}}, IndexBox{{5000, 5000, 5000}, {5008, 5008, 5008}}}) {
        SCOPED_TRACE(testing::Message() << "box " << box.min[0] << "," << box.min[1] << "," << box.min[2]);
        const std::vector<LeafMask> expected = masks_counted(*grid, box);
        expect_same_masks(from_file->active_leaves(box), expected);
        expect_same_masks(in_memory->active_leaves(box), expected);
    }
    const std::vector<LeafMask> all = from_file->active_leaves(kEverything);
    EXPECT_GT(all.size(), 20u);
    // The full leaf, and one voxel of it alone.
    const auto full = std::find_if(all.begin(), all.end(), [](const LeafMask& m) { return m.origin == std::array<std::int32_t, 3>{200, 16, 8}; });
    ASSERT_NE(full, all.end());
    for (std::uint64_t word : full->on) EXPECT_EQ(word, ~std::uint64_t{0});
    const auto one = from_file->active_leaves(IndexBox{{203, 19, 12}, {204, 20, 13}});
    ASSERT_EQ(one.size(), 1u);
    EXPECT_EQ(one[0].on[3], std::uint64_t{1} << (3 * 8 + 4));
}

}  // namespace
}  // namespace vdbmesh
