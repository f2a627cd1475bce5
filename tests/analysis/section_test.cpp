// section_mesh(): exact sections of hand-made boxes and tori (holes, nesting, vertices on the
// plane), the mid-section of the sphere phantom, and the refusal of an open mesh.

#include <gtest/gtest.h>

#include <cmath>

#include "phantom_grid.h"
#include "test_meshes.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/section.h"

namespace vdbmesh::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(SectionMeshTest, BoxGivesItsRectangle) {
    const Section s = section_mesh(box_123(), axis_plane(2, 1.5));
    ASSERT_EQ(s.loops.size(), 1u);
    EXPECT_NEAR(s.area, 2, 1e-12);
    EXPECT_NEAR(s.perimeter, 6, 1e-12);
    EXPECT_GT(s.loops[0].area, 0);  // outer loops run counter-clockwise
    EXPECT_NEAR(s.centroid[0], 0.5, 1e-12);
    EXPECT_NEAR(s.centroid[1], 1, 1e-12);
    EXPECT_NEAR(s.centroid[2], 1.5, 1e-12);
    // A rectangle of width w (along u = x) and height h (along v = y): w h^3 / 12 and h w^3 / 12.
    EXPECT_NEAR(s.second_moments[0], 1 * 8 / 12.0, 1e-12);
    EXPECT_NEAR(s.second_moments[1], 2 * 1 / 12.0, 1e-12);
    EXPECT_NEAR(s.second_moments[2], 0, 1e-12);
    EXPECT_EQ(s.holes(), 0u);
}

TEST(SectionMeshTest, CavityIsAHoleNestedInItsOuterLoop) {
    Mesh mesh = cube({0, 0, 0}, 4);
    const Mesh inner = cube({1, 1, 1}, 1);
    for (const auto& v : inner.vertices) mesh.vertices.push_back(v);
    for (const auto& t : inner.triangles) mesh.triangles.push_back({8 + t[0], 8 + t[2], 8 + t[1]});  // inside out
    const Section s = section_mesh(mesh, axis_plane(0, 1.5));
    ASSERT_EQ(s.loops.size(), 2u);
    EXPECT_NEAR(s.area, 16 - 1, 1e-12);
    EXPECT_NEAR(s.perimeter, 16 + 4, 1e-12);
    EXPECT_EQ(s.loops[1].parent, 0);
    EXPECT_EQ(s.loops[1].depth, 1);
    EXPECT_LT(s.loops[1].area, 0);
    EXPECT_EQ(s.holes(), 1u);
}

TEST(SectionMeshTest, PlaneThroughVerticesGivesTheTorusRings) {
    const int n = 16;
    const Section s = section_mesh(torus(n, 8, 3, 1), axis_plane(2, 0));
    ASSERT_EQ(s.loops.size(), 2u);
    // The outer ring's vertices lie on the plane (counted above it): each is reached through
    // the edge and the diagonal below it, a zero-length segment, so 2n points.
    EXPECT_EQ(s.loops[0].points.size(), std::size_t(2 * n));
    // Regular n-gons with circumradius 4 and 2 (the torus' vertices at z = 0).
    const double ngon = n / 2.0 * std::sin(2 * kPi / n);
    EXPECT_NEAR(s.area, ngon * (16 - 4), 1e-5);
    EXPECT_EQ(s.holes(), 1u);
}

TEST(SectionMeshTest, PlaneMissingTheMeshGivesAnEmptySection) {
    const Section s = section_mesh(box_123(), axis_plane(2, 7));
    EXPECT_TRUE(s.loops.empty());
    EXPECT_EQ(s.area, 0);
    EXPECT_EQ(s.centroid[2], 7);
}

TEST(SectionMeshTest, OpenMeshIsRefused) {
    Mesh mesh = box_123();
    mesh.triangles.pop_back();  // a triangle of the face x = 1, reaching from z = 0 to z = 3
    EXPECT_THROW(section_mesh(mesh, axis_plane(2, 1.5)), Error);
    EXPECT_NO_THROW(section_mesh(mesh, axis_plane(0, 0.5)));  // the cut misses the hole
}

TEST(SectionMeshTest, BadPlanesAreUsageErrors) {
    EXPECT_THROW(make_plane({0, 0, 0}, 1), UsageError);
    EXPECT_THROW(make_plane({0, 0, 1}, NAN), UsageError);
    EXPECT_THROW(axis_plane(3, 1), UsageError);
}

// The figure of issue 11: the mid-section of the 128^3 sphere phantom (radius 40) is one loop
// with an area within 0.5% of pi r^2; the same through a tilted plane.
TEST(SectionMeshTest, SpherePhantomMidSectionIsItsGreatCircle) {
    const PhantomSpec spec = phantom_preset("sphere", {128, 128, 128});
    MeshOptions options;
    options.iso = 0.5;
    const Mesh mesh = mesh_grid(*phantom_scan_grid(spec), options).mesh;
    const double disc = kPi * spec.radius * spec.radius;
    const Section mid = section_mesh(mesh, axis_plane(2, 63.5));
    ASSERT_EQ(mid.loops.size(), 1u);
    EXPECT_NEAR(mid.area, disc, 0.005 * disc);
    EXPECT_NEAR(mid.perimeter, 2 * kPi * spec.radius, 0.005 * 2 * kPi * spec.radius);
    const std::array<double, 3> normal{1, 2, 3};
    const double centre_offset = 63.5 * (1 + 2 + 3) / std::sqrt(14.0);
    const Section tilted = section_mesh(mesh, make_plane(normal, centre_offset));
    ASSERT_EQ(tilted.loops.size(), 1u);
    EXPECT_NEAR(tilted.area, disc, 0.005 * disc);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(tilted.centroid[k], 63.5, 0.05) << k;
}

}  // namespace
}  // namespace vdbmesh::test
