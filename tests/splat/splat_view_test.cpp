// The splat tree read by region (against the whole grid's), and the nodes a camera needs.

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <map>

#include "splat_camera.h"
#include "splat_test_math.h"
#include "test_data.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/splats.h"

namespace vdbmesh {
namespace {

using test::kPi;

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

/// The grid seen as regions in the simplest way the interface allows: the whole grid for any
/// box (outside the box: anything).
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
    // The grid stage's source, whose regions hold only what meets the box: the same tree.
    const SplatTree in_memory = build_splat_tree(*grid_regions_in_memory(grid), SplatOptions{});
    ASSERT_EQ(in_memory.nodes.size(), whole.nodes.size());
    for (std::size_t i = 0; i < whole.nodes.size(); ++i) {
        EXPECT_EQ(in_memory.nodes[i].centre, whole.nodes[i].centre) << i;
        EXPECT_EQ(in_memory.nodes[i].normal, whole.nodes[i].normal) << i;
        EXPECT_EQ(in_memory.nodes[i].radius, whole.nodes[i].radius) << i;
    }
    // A .vdb file read by region (what `vdbmesh view` of a .vdb builds from): the same nodes, field by field.
    const test::ScratchDir dir;
    write_vdb(*grid, dir / "sphere.vdb");
    const SplatTree from_file = build_splat_tree(*open_vdb_regions(dir / "sphere.vdb"), SplatOptions{});
    ASSERT_EQ(from_file.nodes.size(), whole.nodes.size());
    for (std::size_t i = 0; i < whole.nodes.size(); ++i) {
        const SplatNode &a = from_file.nodes[i], &b = whole.nodes[i];
        test::expect_same_splat(a, b, i);
        EXPECT_EQ(a.first_child, b.first_child) << i;
        EXPECT_EQ(a.child_count, b.child_count) << i;
    }
}

TEST(SplatRegions, SameTreeForOneAndTwoThreadsReadByRegion) {
    // The next node's region is read while a node's cells are fitted: the file's bytes must
    // not depend on how the two interleave, nor on the threads fitting.
    const test::ScratchDir dir;
    write_vdb(*sphere_across_nodes(), dir / "sphere.vdb");
    const auto regions = open_vdb_regions(dir / "sphere.vdb");
    tbb::task_arena(1).execute([&] { write_splat_file(build_splat_tree(*regions, SplatOptions{}), dir / "one.splat"); });
    tbb::task_arena(2).execute([&] { write_splat_file(build_splat_tree(*regions, SplatOptions{}), dir / "two.splat"); });
    const auto bytes = [](const std::filesystem::path& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    };
    const std::string one = bytes(dir / "one.splat");
    EXPECT_GT(one.size(), 10000u);
    EXPECT_EQ(one, bytes(dir / "two.splat"));
}

class SplatSelectionTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() { tree_ = build_splat_tree(*sphere_across_nodes(), SplatOptions{}); }
    static SplatTree tree_;
};
SplatTree SplatSelectionTest::tree_;

TEST_F(SplatSelectionTest, AFarCameraGetsFewCoarseNodes) {
    SplatView camera = test::camera_at({0, 0, 20000});  // the sphere ~3 pixels across
    const SplatSelection selection = select_splats(tree_, camera);
    EXPECT_TRUE(selection.complete);
    EXPECT_GT(selection.nodes.size(), 10u);
    EXPECT_LT(selection.nodes.size(), 100u);
    EXPECT_GT(selection.finest_level, kSplatLeafLevel);
    EXPECT_GE(selection.cut_level, selection.finest_level);  // shown for their children
}

TEST_F(SplatSelectionTest, ACloseCameraGetsEveryFacingSurfaceAtFullDetail) {
    SplatView camera = test::camera_at({0, 0, 150});
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
    SplatView camera = test::camera_at({0, 0, 150});
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
    const SplatView camera = test::camera_at({0, 0, 150}, openvdb::Vec3d(0, 0, 1000));  // looking away
    EXPECT_TRUE(select_splats(tree_, camera).nodes.empty());
}

}  // namespace
}  // namespace vdbmesh
