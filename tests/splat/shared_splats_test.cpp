// The splat hierarchy of a shared tree (result matching) against the plain tree of the grid it
// represents, and the nodes a camera needs from it.

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "splat_camera.h"
#include "splat_test_math.h"
#include "vdbmesh/shared_splats.h"
#include "vdbmesh/shared_tree.h"

namespace vdbmesh {
namespace {

using test::kPi;

/// A row of eight 128^3 nodes along x, each holding the same sphere (radius 20 voxels, a signed
/// distance negative inside in a band of 3): the six inner nodes have the same neighbourhood,
/// so their subtree is fitted once.
SharedTree sphere_row() {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(3.0f);
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
    auto accessor = grid->getAccessor();
    for (int node = 0; node < 8; ++node) {
        const openvdb::Vec3d centre(node * 128 + 60.3, 61.7, 62.2);
        for (int z = 38; z <= 86; ++z)
            for (int y = 38; y <= 86; ++y)
                for (int x = node * 128 + 38; x <= node * 128 + 86; ++x) {
                    const double d = (openvdb::Vec3d(x, y, z) - centre).length() - 20;
                    if (std::abs(d) < 3) accessor.setValue(openvdb::Coord(x, y, z), float(d));
                }
    }
    return build_shared_tree(*grid);
}

SplatOptions level_set() {
    SplatOptions options;
    options.inside = Inside::below;
    return options;
}

/// Every node of the represented tree, placed (the top's placed nodes are their subtrees' roots).
std::vector<SplatNode> expanded(const SharedSplatTree& tree) {
    std::vector<SplatNode> nodes(tree.top.nodes.begin(), tree.top.nodes.begin() + std::ptrdiff_t(tree.first_placed));
    for (const auto& placed : tree.placed)
        for (SplatNode n : tree.subtrees[placed.subtree]) {
            for (int a = 0; a < 3; ++a) n.centre[a] = float(n.centre[a] + placed.offset[a]);
            nodes.push_back(n);
        }
    return nodes;
}

/// Each node of @a a has one of @a b at its level within @a close world units (centre and
/// radius) and 1e-3 (normal), each matched once.
void expect_same_nodes(const std::vector<SplatNode>& a, std::vector<SplatNode> b, double close) {
    ASSERT_EQ(a.size(), b.size());
    const auto by_x = [](const SplatNode& n, const SplatNode& m) { return std::tie(n.level, n.centre[0]) < std::tie(m.level, m.centre[0]); };
    std::sort(b.begin(), b.end(), by_x);
    std::vector<bool> matched(b.size(), false);
    for (const SplatNode& n : a) {
        SplatNode low = n;
        low.centre[0] -= float(close);
        bool found = false;
        for (auto it = std::lower_bound(b.begin(), b.end(), low, by_x); it != b.end() && it->level == n.level && it->centre[0] <= n.centre[0] + close; ++it) {
            const std::size_t i = std::size_t(it - b.begin());
            bool same = !matched[i] && std::abs(it->radius - n.radius) <= close;
            // A cone wider than a half sphere: the children's normals nearly cancel, so the
            // direction of their mean is decided by rounding. A cell whose gradients cancel
            // (a saddle at its centre) takes the sign of its plane's normal from rounding too.
            const bool any_normal = n.cone > kPi / 2;
            bool same_normal = true, opposite_normal = true;
            for (int k = 0; k < 3; ++k) {
                same = same && std::abs(it->centre[k] - n.centre[k]) <= close;
                same_normal = same_normal && std::abs(it->normal[k] - n.normal[k]) <= 1e-3;
                opposite_normal = opposite_normal && std::abs(it->normal[k] + n.normal[k]) <= 1e-3;
            }
            same = same && (any_normal || same_normal || opposite_normal);
            if (same) {
                matched[i] = found = true;
                break;
            }
        }
        ASSERT_TRUE(found) << "level " << int(n.level) << " at " << n.centre[0] << " " << n.centre[1] << " " << n.centre[2];
    }
}

/// Centres differ by float rounding: a subtree is fitted at one place and translated (a centre
/// of 500 world units is exact to about 3e-5), inner nodes average those.
constexpr double kClose = 1e-3;

TEST(SharedSplats, SameNodesAsThePlainTreeOfTheExpandedGrid) {
    const SharedTree shared = sphere_row();
    const SharedSplatTree tree = build_splat_tree(shared, level_set());
    const SplatTree plain = build_splat_tree(*to_float_grid(shared), level_set());
    ASSERT_FALSE(plain.nodes.empty());
    EXPECT_EQ(tree.represented_nodes(), plain.nodes.size());
    // Result matching: the six inner nodes' subtree fitted once, the two outer ones apart.
    EXPECT_EQ(tree.placed.size(), 8u);
    EXPECT_EQ(tree.subtrees.size(), 3u);
    expect_same_nodes(expanded(tree), plain.nodes, kClose);
}

TEST(SharedSplats, AViewSelectsWhatThePlainTreeGives) {
    const SharedTree shared = sphere_row();
    const SharedSplatTree tree = build_splat_tree(shared, level_set());
    const SplatTree plain = build_splat_tree(*to_float_grid(shared), level_set());
    for (double distance : {800.0, 60.0}) {
        SplatView view = test::camera_at({250 + 0.1 * distance, 30 + 0.5 * distance, 30 + 0.86 * distance}, openvdb::Vec3d(250, 30, 30));
        view.budget = 1'000'000;  // not reached: which nodes refine is not a matter of ties in size
        const SharedSplatSelection selected = select_splats(tree, view);
        const SplatSelection reference = select_splats(plain, view);
        EXPECT_EQ(selected.summary.finest_level, reference.finest_level) << distance;
        EXPECT_EQ(selected.summary.cut_level, reference.cut_level) << distance;
        EXPECT_TRUE(selected.summary.complete);
        // The same up to the children of the nodes whose normal rounding decides (see above),
        // which the cone test may cull on one side and not the other.
        EXPECT_NEAR(double(selected.nodes.size()), double(reference.nodes.size()), 0.01 * double(reference.nodes.size())) << distance;
    }
}

}  // namespace
}  // namespace vdbmesh
