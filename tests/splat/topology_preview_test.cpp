// The topology preview (build_topology_preview): a splat per leaf of a sphere's active band,
// judged against the sphere itself; made without reading a value.

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <stdexcept>

#include "test_data.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/splats.h"

namespace vdbmesh {
namespace {

constexpr double kRadius = 40;     // voxels
constexpr double kHalfBand = 1.5;  // voxels: the active band |distance| <= 1.5, as a converted scan's
const openvdb::Vec3d kCentre(2.3, -1.6, 0.7);

/// The signed distance to the sphere (positive inside) on the band's voxels only, all active.
openvdb::FloatGrid::Ptr sphere_band() {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(-3.0f);
    auto accessor = grid->getAccessor();
    for (int z = -44; z <= 44; ++z)
        for (int y = -44; y <= 44; ++y)
            for (int x = -44; x <= 44; ++x) {
                const double d = kRadius - (openvdb::Vec3d(x, y, z) - kCentre).length();
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

openvdb::Vec3d vec(const std::array<float, 3>& a) { return openvdb::Vec3d(a[0], a[1], a[2]); }

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
        const openvdb::Vec3d radial = vec(node.centre) - kCentre;
        // The centroid of the band's voxels in a leaf lies within the band, but for the sag of
        // the sphere across a leaf (8 voxels: 8^2 * 3 / (8 * 40) = 0.6 voxel on its diagonal).
        EXPECT_NEAR(radial.length(), kRadius, kHalfBand + 0.6) << "at " << radial;
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
