#pragma once
// Helpers of the shared-tree tests: random sparse grids and voxel-by-voxel grid equality.

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <random>
#include <vector>

namespace vdbmesh {

/// A sparse level-set-like grid: random leaves (some copied to several places), inside and
/// outside tiles at levels 1 and 2, background outside.
inline openvdb::FloatGrid::Ptr random_grid(unsigned seed, double voxel = 0.5) {
    openvdb::initialize();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    const float bg = 1.0f;
    auto grid = openvdb::FloatGrid::create(bg);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    auto& tree = grid->tree();
    std::uniform_int_distribution<int> pos(-3, 3);
    std::vector<openvdb::FloatTree::LeafNodeType> templates;
    for (int t = 0; t < 4; ++t) {
        openvdb::FloatTree::LeafNodeType leaf(openvdb::Coord(0), bg);
        for (openvdb::Index i = 0; i < 512; ++i) {
            // Smooth-ish values so that surfaces are not all noise, plus noise.
            leaf.setValueOn(i, value(rng));
            if (rng() % 4 == 0) leaf.setValueOff(i);
        }
        templates.push_back(leaf);
    }
    for (int n = 0; n < 60; ++n) {
        const openvdb::Coord origin(pos(rng) * 8, pos(rng) * 8, pos(rng) * 8);
        if (tree.probeConstLeaf(origin)) continue;
        auto* leaf = new openvdb::FloatTree::LeafNodeType(templates[rng() % templates.size()]);
        leaf->setOrigin(origin);
        if (rng() % 3 == 0) leaf->setValueOn(openvdb::Index(rng() % 512), value(rng));  // a near copy
        tree.addLeaf(leaf);
    }
    // Tiles: an inside 8^3 tile, an inside 128^3 tile far away, an active tile.
    tree.addTile(1, openvdb::Coord(64, 0, 0), -1.0f, false);
    tree.addTile(1, openvdb::Coord(72, 0, 0), 0.25f, true);
    tree.addTile(2, openvdb::Coord(128, 0, 0), -1.0f, false);
    tree.addTile(1, openvdb::Coord(-512, 0, 0), -0.5f, false);  // in an n2 node of its own
    return grid;
}

/// Every voxel's value and state equal in both grids (over the union of their extents).
inline void expect_same_grid(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
    EXPECT_EQ(a.background(), b.background());
    EXPECT_EQ(a.tree().activeVoxelCount(), b.tree().activeVoxelCount());
    auto check = [](const openvdb::FloatGrid& x, const openvdb::FloatGrid& y) {
        auto acc = y.getConstAccessor();
        std::size_t bad = 0;
        for (auto it = x.tree().cbeginValueAll(); it; ++it) {
            if (it.getVoxelCount() > 1) {
                const openvdb::CoordBBox box = it.getBoundingBox();
                // Tiles: sample corners and centre.
                const openvdb::Coord mid((box.min().x() + box.max().x()) / 2, (box.min().y() + box.max().y()) / 2,
                                         (box.min().z() + box.max().z()) / 2);
                for (const openvdb::Coord& c : {box.min(), box.max(), mid}) {
                    if (acc.getValue(c) != *it || acc.isValueOn(c) != it.isValueOn()) ++bad;
                }
            } else if (acc.getValue(it.getCoord()) != *it || acc.isValueOn(it.getCoord()) != it.isValueOn()) {
                ++bad;
            }
        }
        return bad;
    };
    EXPECT_EQ(check(a, b), 0u);
    EXPECT_EQ(check(b, a), 0u);
}

}  // namespace vdbmesh
