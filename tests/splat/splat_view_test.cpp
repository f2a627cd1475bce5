// The splat tree read by region (against the whole grid's), and the nodes a camera needs.

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <map>

#include "vdbmesh/grid_region.h"
#include "vdbmesh/splats.h"

namespace vdbmesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A sphere of radius 40 voxels centred near the origin, so that it spans eight 128^3 nodes:
/// the signed distance (positive inside) in a band of 3 voxels, inside tiles and voxels deeper.
openvdb::FloatGrid::Ptr sphere_across_nodes() {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(-3.0f);
    auto accessor = grid->getAccessor();
    const openvdb::Vec3d centre(2.3, -1.6, 0.7);
    for (int z = -44; z <= 44; ++z)
        for (int y = -44; y <= 44; ++y)
            for (int x = -44; x <= 44; ++x) {
                const double d = 40 - (openvdb::Vec3d(x, y, z) - centre).length();
                if (d > -3) accessor.setValue(openvdb::Coord(x, y, z), float(std::min(d, 3.0)));
            }
    return grid;
}

/// The grid seen as regions (grid_regions_in_memory() belongs to another stage's work): the
/// whole grid for any box, which the interface allows (outside the box: anything).
class WholeGridRegions : public GridRegionSource {
public:
    explicit WholeGridRegions(openvdb::FloatGrid::Ptr grid) : grid_(std::move(grid)) {}
    std::shared_ptr<const openvdb::FloatGrid> description() const override { return openvdb::gridPtrCast<openvdb::FloatGrid>(grid_->copyGridWithNewTree()); }
    std::vector<NodeWeight> nodes() const override {
        std::map<std::array<std::int32_t, 3>, std::uint64_t> counts;  // ordered z-major below
        for (auto v = grid_->cbeginValueOn(); v; ++v) {
            const openvdb::Coord c = v.getCoord() & ~(kNodeVoxels - 1);
            counts[{c.z(), c.y(), c.x()}] += v.getVoxelCount();
        }
        std::vector<NodeWeight> nodes;
        for (const auto& [zyx, count] : counts) nodes.push_back(NodeWeight{{zyx[2], zyx[1], zyx[0]}, count});
        return nodes;
    }
    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox&) const override { return grid_->deepCopy(); }
    std::uint64_t estimated_bytes(const IndexBox&) const override { return grid_->memUsage(); }

private:
    openvdb::FloatGrid::Ptr grid_;
};

/// three.js's camera at @a eye looking at @a target (up +y), fov 45 degrees, 900 x 700.
SplatView camera_at(const std::array<double, 3>& eye, const openvdb::Vec3d& target = openvdb::Vec3d(0)) {
    const openvdb::Vec3d e(eye[0], eye[1], eye[2]);
    const openvdb::Vec3d back = (e - target).unitSafe(), right = openvdb::Vec3d(0, 1, 0).cross(back).unitSafe(), up = back.cross(right);
    const double fov = 45 * kPi / 180, aspect = 900.0 / 700.0, near = 0.1, far = 10000;
    const double f = 1 / std::tan(fov / 2);
    // Row-major view (world to camera) and projection, multiplied, then stored column-major.
    const double view[4][4] = {{right.x(), right.y(), right.z(), -right.dot(e)},
                               {up.x(), up.y(), up.z(), -up.dot(e)},
                               {back.x(), back.y(), back.z(), -back.dot(e)},
                               {0, 0, 0, 1}};
    const double proj[4][4] = {{f / aspect, 0, 0, 0},
                               {0, f, 0, 0},
                               {0, 0, (far + near) / (near - far), 2 * far * near / (near - far)},
                               {0, 0, -1, 0}};
    SplatView camera;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            double sum = 0;
            for (int k = 0; k < 4; ++k) sum += proj[r][k] * view[k][c];
            camera.view_projection[c * 4 + r] = sum;
        }
    camera.eye = eye;
    camera.focal_pixels = 700 / (2 * std::tan(fov / 2));
    return camera;
}

/// Each node's parent (the root's: itself).
std::vector<std::uint32_t> parents(const SplatTree& tree) {
    std::vector<std::uint32_t> parent(tree.nodes.size(), 0);
    for (std::uint32_t i = 0; i < tree.nodes.size(); ++i)
        for (std::uint32_t c = 0; c < tree.nodes[i].child_count; ++c) parent[tree.nodes[i].first_child + c] = i;
    return parent;
}

TEST(SplatRegions, ReadByRegionGivesTheWholeGridsTree) {
    const auto grid = sphere_across_nodes();
    const WholeGridRegions regions(grid);
    ASSERT_EQ(regions.nodes().size(), 8u);  // the sphere straddles the nodes' corner at the origin
    const SplatTree whole = build_splat_tree(*grid, SplatOptions{});
    const SplatTree by_region = build_splat_tree(regions, SplatOptions{});
    ASSERT_GT(whole.nodes.size(), 1000u);
    ASSERT_EQ(by_region.nodes.size(), whole.nodes.size());
    for (std::size_t i = 0; i < whole.nodes.size(); ++i) {
        EXPECT_EQ(by_region.nodes[i].centre, whole.nodes[i].centre) << i;
        EXPECT_EQ(by_region.nodes[i].radius, whole.nodes[i].radius) << i;
        EXPECT_EQ(by_region.nodes[i].child_count, whole.nodes[i].child_count) << i;
    }
}

class SplatSelectionTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() { tree_ = build_splat_tree(*sphere_across_nodes(), SplatOptions{}); }
    static SplatTree tree_;
};
SplatTree SplatSelectionTest::tree_;

TEST_F(SplatSelectionTest, AFarCameraGetsFewCoarseNodes) {
    SplatView camera = camera_at({0, 0, 20000});  // the sphere ~3 pixels across
    const SplatSelection selection = select_splats(tree_, camera);
    EXPECT_TRUE(selection.complete);
    EXPECT_LT(selection.nodes.size(), 100u);
    EXPECT_GT(selection.finest_level, kSplatLeafLevel);
}

TEST_F(SplatSelectionTest, ACloseCameraGetsEveryFacingSurfaceAtFullDetail) {
    SplatView camera = camera_at({0, 0, 150});
    camera.pixel_size = 0.5;  // finer than any splat here: everything visible down to the finest
    const SplatSelection selection = select_splats(tree_, camera);
    EXPECT_TRUE(selection.complete);
    // A cut of the tree: every node selected is childless here, and every childless node
    // facing the eye (its normal within 80 degrees of the eye's direction) is selected;
    // the back is culled.
    const std::vector<bool> chosen = [&] {
        std::vector<bool> c(tree_.nodes.size(), false);
        for (std::uint32_t i : selection.nodes) c[i] = true;
        return c;
    }();
    std::size_t facing = 0, facing_away_shown = 0;
    std::uint8_t facing_finest = kSplatRootLevel;  // most of this sphere collapses to level 1
    for (std::uint32_t i = 0; i < tree_.nodes.size(); ++i) {
        const SplatNode& n = tree_.nodes[i];
        if (chosen[i]) EXPECT_EQ(n.child_count, 0u);
        if (n.child_count != 0) continue;
        const openvdb::Vec3d to_eye = (openvdb::Vec3d(0, 0, 150) - openvdb::Vec3d(n.centre[0], n.centre[1], n.centre[2])).unitSafe();
        const double cosine = to_eye.dot(openvdb::Vec3d(n.normal[0], n.normal[1], n.normal[2]));
        if (cosine > std::cos(80 * kPi / 180)) {
            ++facing;
            facing_finest = std::min(facing_finest, n.level);
            EXPECT_TRUE(chosen[i]) << i;
        }
        if (cosine < -0.5 && chosen[i]) ++facing_away_shown;
    }
    EXPECT_GT(facing, 200u);
    EXPECT_EQ(facing_away_shown, 0u);
    EXPECT_EQ(selection.finest_level, facing_finest);
}

TEST_F(SplatSelectionTest, TheBudgetHoldsAndTheLargestAreRefinedFirst) {
    SplatView camera = camera_at({0, 0, 150});
    camera.pixel_size = 0.5;
    camera.budget = 60;
    const SplatSelection selection = select_splats(tree_, camera);
    EXPECT_FALSE(selection.complete);
    EXPECT_LE(selection.nodes.size(), 60u);
    EXPECT_GT(selection.nodes.size(), 30u);
    // A cut: no selected node is an ancestor of another.
    const auto parent = parents(tree_);
    std::vector<bool> chosen(tree_.nodes.size(), false);
    for (std::uint32_t i : selection.nodes) chosen[i] = true;
    for (std::uint32_t i : selection.nodes)
        for (std::uint32_t a = parent[i]; a != 0; a = parent[a]) EXPECT_FALSE(chosen[a]) << i << " under " << a;
}

TEST_F(SplatSelectionTest, NothingWhenTheModelIsBehindTheCamera) {
    const SplatView camera = camera_at({0, 0, 150}, openvdb::Vec3d(0, 0, 1000));  // looking away
    EXPECT_TRUE(select_splats(tree_, camera).nodes.empty());
}

}  // namespace
}  // namespace vdbmesh
