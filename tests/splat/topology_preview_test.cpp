// The topology preview (build_topology_preview): a splat per leaf of a sphere's active band,
// judged against the sphere itself; made without reading a value.

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <vector>
#include <stdexcept>

#include "splat_test_math.h"
#include "test_data.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/splats.h"

namespace vdbmesh {
namespace {

using test::vec;

constexpr double kBandRadius = 40;  // voxels
constexpr double kHalfBand = 1.5;  // voxels: the active band |distance| <= 1.5, as a converted scan's
const openvdb::Vec3d kBandCentre(2.3, -1.6, 0.7);

/// The signed distance to the sphere (positive inside) on the band's voxels only, all active.
openvdb::FloatGrid::Ptr sphere_band() {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(-3.0f);
    auto accessor = grid->getAccessor();
    for (int z = -44; z <= 44; ++z)
        for (int y = -44; y <= 44; ++y)
            for (int x = -44; x <= 44; ++x) {
                const double d = kBandRadius - (openvdb::Vec3d(x, y, z) - kBandCentre).length();
                if (std::abs(d) <= kHalfBand) accessor.setValue(openvdb::Coord(x, y, z), float(d));
            }
    return grid;
}

/// The leaves' masks of a source whose values cannot be read: what the preview may use.
class TopologyOnly final : public GridRegionSource {
public:
    explicit TopologyOnly(const std::shared_ptr<const GridRegionSource>& whole) : whole_(whole) {}
    std::shared_ptr<const openvdb::FloatGrid> description() const override { return whole_->description(); }
    std::vector<NodeWeight> nodes() const override { return whole_->nodes(); }
    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox&) const override { throw std::logic_error("a value was read"); }
    std::uint64_t estimated_bytes(const IndexBox& box) const override { return whole_->estimated_bytes(box); }
    std::vector<LeafMask> active_leaves(const IndexBox& box) const override { return whole_->active_leaves(box); }

private:
    std::shared_ptr<const GridRegionSource> whole_;
};

TEST(TopologyPreview, ASplatPerLeafAcrossTheSphereBandMadeWithoutReadingAValue) {
    const auto grid = sphere_band();
    const TopologyOnly source(grid_regions_in_memory(grid));
    const SplatTree tree = build_topology_preview(source);
    ASSERT_FALSE(tree.nodes.empty());
    EXPECT_EQ(tree.nodes[0].level, kSplatRootLevel);
    EXPECT_EQ(tree.leaf_count(), grid->tree().leafCount());
    std::size_t tilted = 0;
    for (const SplatNode& node : tree.nodes) {
        EXPECT_FLOAT_EQ(node.cone, float(3.14159265358979323846));  // the sign is unknown: never culled
        if (node.child_count != 0) continue;
        EXPECT_EQ(node.level, kSplatLeafLevel);
        const openvdb::Vec3d radial = vec(node.centre) - kBandCentre;
        // The centroid of the band's voxels in a leaf lies within the band, but for the sag of
        // the sphere across a leaf (8 voxels: 8^2 * 3 / (8 * 40) = 0.6 voxel on its diagonal).
        EXPECT_NEAR(radial.length(), kBandRadius, kHalfBand + 0.6) << "at " << radial;
        // A leaf's disc reaches from the centroid past the farthest active voxel's centre by
        // half a voxel's diagonal: at least that, at most the leaf's diagonal and that.
        EXPECT_LE(node.radius, std::sqrt(3.0) * 7.5 + 0.01);
        EXPECT_GE(node.radius, std::sqrt(3.0) / 2 - 0.01);
        // Across the band: along the radius up to sign. Leaves the band only grazes hold a
        // few voxels whose thinnest direction is anything: at most 10% may tilt over 30 degrees.
        if (std::abs(radial.unit().dot(vec(node.normal))) < std::cos(30 * 3.14159265358979323846 / 180)) ++tilted;
    }
    EXPECT_LE(tilted, tree.leaf_count() / 10);
    // The root encloses every leaf's disc.
    for (const SplatNode& node : tree.nodes)
        if (node.child_count == 0)
            EXPECT_LE((vec(node.centre) - vec(tree.nodes[0].centre)).length() + node.radius, tree.nodes[0].radius * (1 + 1e-5));
}

/// A leaf's splat as the preview defines it, summed voxel by voxel (double sums of each active
/// voxel's coordinates and their products, Eigen's solver, the farthest of every voxel), on a
/// grid of unit voxels at the origin (world = index).
SplatNode reference_leaf_splat(const openvdb::FloatTree::LeafNodeType& leaf) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
    std::uint32_t count = 0;
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
        const openvdb::Coord offset = voxel.getCoord() - leaf.origin();
        const Eigen::Vector3d p(offset.x(), offset.y(), offset.z());
        sum += p;
        outer += p * p.transpose();
        ++count;
    }
    const Eigen::Vector3d centroid = sum / count;
    const Eigen::Matrix3d covariance = outer / count - centroid * centroid.transpose();
    const Eigen::Vector3d normal = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvectors().col(0);
    double farthest = 0;
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
        const openvdb::Coord offset = voxel.getCoord() - leaf.origin();
        farthest = std::max(farthest, (Eigen::Vector3d(offset.x(), offset.y(), offset.z()) - centroid).squaredNorm());
    }
    SplatNode node;
    const Eigen::Vector3d world = centroid + Eigen::Vector3d(leaf.origin().x(), leaf.origin().y(), leaf.origin().z());
    node.centre = {float(world.x()), float(world.y()), float(world.z())};
    openvdb::Vec3d unit(float(normal.x()), float(normal.y()), float(normal.z()));  // as the tree stores it, then normalised
    unit.normalize();
    node.normal = {float(unit.x()), float(unit.y()), float(unit.z())};
    node.radius = float(std::sqrt(farthest) + std::sqrt(3.0) / 2);
    return node;
}

TEST(TopologyPreview, EachLeafsSplatIsTheVoxelByVoxelOneExactly) {
    const auto grid = sphere_band();
    const SplatTree tree = build_topology_preview(*grid_regions_in_memory(grid));
    std::vector<SplatNode> expected, leaves;
    for (auto leaf = grid->tree().cbeginLeaf(); leaf; ++leaf) expected.push_back(reference_leaf_splat(*leaf));
    for (const SplatNode& node : tree.nodes)
        if (node.child_count == 0) leaves.push_back(node);
    auto by_centre = [](const SplatNode& a, const SplatNode& b) { return a.centre < b.centre; };
    std::sort(expected.begin(), expected.end(), by_centre);
    std::sort(leaves.begin(), leaves.end(), by_centre);
    ASSERT_EQ(leaves.size(), expected.size());
    for (std::size_t i = 0; i < leaves.size(); ++i) {
        EXPECT_EQ(leaves[i].centre, expected[i].centre) << i;
        // Up to sign: the merge aligns the unsigned normals of siblings (align_normals).
        const std::array<float, 3> flipped{-expected[i].normal[0], -expected[i].normal[1], -expected[i].normal[2]};
        EXPECT_TRUE(leaves[i].normal == expected[i].normal || leaves[i].normal == flipped) << i;
        EXPECT_EQ(leaves[i].radius, expected[i].radius) << i;
    }
}

TEST(TopologyPreview, TheSameTreeFromTheVdbTopology) {
    const auto grid = sphere_band();
    test::ScratchDir dir;
    write_vdb(*grid, dir / "band.vdb");
    const SplatTree from_file = build_topology_preview(*open_vdb_regions(dir / "band.vdb"));
    const SplatTree in_memory = build_topology_preview(*grid_regions_in_memory(grid));
    ASSERT_EQ(from_file.nodes.size(), in_memory.nodes.size());
    for (std::size_t i = 0; i < from_file.nodes.size(); ++i) {
        EXPECT_EQ(from_file.nodes[i].centre, in_memory.nodes[i].centre);
        EXPECT_EQ(from_file.nodes[i].normal, in_memory.nodes[i].normal);
        EXPECT_EQ(from_file.nodes[i].radius, in_memory.nodes[i].radius);
    }
}

}  // namespace
}  // namespace vdbmesh
