#include "region_test_util.h"

#include <gtest/gtest.h>

#include <map>
#include <tuple>

namespace vdbmesh::test {

namespace {

/// The box of every leaf and tile of @a grid, widened by a leaf: outside it lies background.
openvdb::CoordBBox bounds_of_values(const openvdb::FloatGrid& grid) {
    openvdb::CoordBBox bounds;
    grid.tree().evalLeafBoundingBox(bounds);
    auto tile = grid.tree().cbeginValueAll();
    tile.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);  // tiles, not voxels
    for (; tile; ++tile) {
        if (!tile.isValueOn() && *tile == grid.background()) continue;  // every unused entry of a node
        openvdb::CoordBBox box;
        tile.getBoundingBox(box);
        bounds.expand(box);
    }
    bounds.expand(8);
    return bounds;
}

}  // namespace

void expect_same_inside(const openvdb::FloatGrid& whole, const openvdb::FloatGrid& part, const IndexBox& box) {
    const openvdb::CoordBBox bounds = bounds_of_values(whole);
    const openvdb::CoordBBox clipped(openvdb::Coord::maxComponent(bounds.min(), openvdb::Coord(box.min[0], box.min[1], box.min[2])),
                                     openvdb::Coord::minComponent(bounds.max(), openvdb::Coord(box.max[0] - 1, box.max[1] - 1, box.max[2] - 1)));
    if (clipped.empty()) return;  // its iterator would run far beyond
    const auto expected = whole.getConstAccessor();
    const auto actual = part.getConstAccessor();
    std::size_t wrong = 0;
    for (auto xyz = clipped.begin(); xyz && wrong < 5; ++xyz) {
        if (expected.getValue(*xyz) == actual.getValue(*xyz) && expected.isValueOn(*xyz) == actual.isValueOn(*xyz)) continue;
        ++wrong;
        ADD_FAILURE() << "voxel " << *xyz << ": " << actual.getValue(*xyz) << (actual.isValueOn(*xyz) ? " on" : " off") << ", expected "
                      << expected.getValue(*xyz) << (expected.isValueOn(*xyz) ? " on" : " off");
    }
}

std::vector<NodeWeight> nodes_counted(const openvdb::FloatGrid& grid) {
    std::map<std::tuple<int, int, int>, std::uint64_t> counts;  // (z, y, x)
    for (auto value = grid.cbeginValueOn(); value; ++value) {
        openvdb::CoordBBox box;
        value.getBoundingBox(box);
        for (int z = box.min().z() & ~(kNodeVoxels - 1); z <= box.max().z(); z += kNodeVoxels)
            for (int y = box.min().y() & ~(kNodeVoxels - 1); y <= box.max().y(); y += kNodeVoxels)
                for (int x = box.min().x() & ~(kNodeVoxels - 1); x <= box.max().x(); x += kNodeVoxels) {
                    const openvdb::CoordBBox node = openvdb::CoordBBox::createCube(openvdb::Coord(x, y, z), kNodeVoxels);
                    const openvdb::CoordBBox shared(openvdb::Coord::maxComponent(node.min(), box.min()),
                                                    openvdb::Coord::minComponent(node.max(), box.max()));
                    counts[{z, y, x}] += shared.volume();
                }
    }
    std::vector<NodeWeight> nodes;
    for (const auto& [zyx, count] : counts) nodes.push_back({{std::get<2>(zyx), std::get<1>(zyx), std::get<0>(zyx)}, count});
    return nodes;
}

void expect_same_nodes(const std::vector<NodeWeight>& actual, const std::vector<NodeWeight>& expected) {
    ASSERT_EQ(actual.size(), expected.size());
    for (std::size_t i = 0; i < actual.size(); ++i) {
        EXPECT_EQ(actual[i].origin, expected[i].origin) << "node " << i;
        EXPECT_EQ(actual[i].active_voxels, expected[i].active_voxels) << "node " << i;
    }
}

}  // namespace vdbmesh::test
