// analyze_mesh() on tiny meshes with known answers, and each defect caught.
#include <gtest/gtest.h>

#include "test_meshes.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"

namespace vdbmesh {
namespace {

using test::cube;
using test::tetrahedron;

// Integrals of meshes with float coordinates that are small integers are exact up to
// double rounding of a few dozen operations.
constexpr double kTol = 1e-12;

TEST(AnalyzeMeshTest, TetrahedronIsCleanWithExactIntegrals) {
    const MeshAnalysis r = analyze_mesh(tetrahedron());
    EXPECT_TRUE(r.is_clean());
    EXPECT_EQ(r.triangles, 4u);
    EXPECT_EQ(r.vertices, 4u);
    EXPECT_EQ(r.edges, 6u);
    EXPECT_EQ(r.euler_characteristic, 2);
    EXPECT_EQ(r.genus, 0);
    EXPECT_EQ(r.components, 1u);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.outward);
    EXPECT_NEAR(r.volume, 1.0 / 6, kTol);
    EXPECT_NEAR(r.area, 1.5 + std::sqrt(3.0) / 2, kTol);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.centroid[k], 0.25, kTol);
    // Central second moments: int x^2 = 1/60, int xy = 1/120, minus V c c^T with c = 1/4.
    const double diagonal = 2 * (1.0 / 60 - 1.0 / 96), off_diagonal = -(1.0 / 120 - 1.0 / 96);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(r.inertia[i][j], i == j ? diagonal : off_diagonal, kTol) << i << j;
    }
    EXPECT_NEAR(r.min_angle_deg, 45.0, 1e-9);
    EXPECT_EQ(r.small_angle_share, 0.0);
}

TEST(AnalyzeMeshTest, OffsetCubeHasExactIntegrals) {
    const MeshAnalysis r = analyze_mesh(cube({1, 2, -1}, 2));
    EXPECT_TRUE(r.is_clean());
    EXPECT_EQ(r.genus, 0);
    EXPECT_EQ(r.euler_characteristic, 2);
    EXPECT_NEAR(r.volume, 8.0, kTol);
    EXPECT_NEAR(r.area, 24.0, kTol);
    EXPECT_NEAR(r.centroid[0], 2.0, kTol);
    EXPECT_NEAR(r.centroid[1], 3.0, kTol);
    EXPECT_NEAR(r.centroid[2], 0.0, kTol);
    // A solid cube of mass 8 and side 2: I = m (s^2 + s^2) / 12 = 16/3 on the diagonal.
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(r.inertia[i][j], i == j ? 16.0 / 3 : 0.0, kTol);
    }
    EXPECT_NEAR(r.min_angle_deg, 45.0, 1e-9);
}

TEST(AnalyzeMeshTest, TorusHasGenusOne) {
    const MeshAnalysis r = analyze_mesh(test::torus());
    EXPECT_TRUE(r.is_clean());
    EXPECT_EQ(r.euler_characteristic, 0);
    EXPECT_EQ(r.genus, 1);
    EXPECT_EQ(r.components, 1u);
    // The inscribed polyhedron's volume is below 2 pi^2 R r^2 = 59.2 but close.
    EXPECT_GT(r.volume, 50.0);
    EXPECT_LT(r.volume, 2 * M_PI * M_PI * 3);
}

TEST(AnalyzeMeshTest, InsideOutMeshIsNotOutward) {
    Mesh mesh = cube();
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
    const MeshAnalysis r = analyze_mesh(mesh);
    EXPECT_FALSE(r.outward);
    EXPECT_EQ(r.negative_components, 1u);
    EXPECT_EQ(r.misoriented_edges, 0u);
    EXPECT_NEAR(r.volume, -1.0, kTol);
    EXPECT_FALSE(r.is_clean());
}

TEST(AnalyzeMeshTest, HoleLeavesBoundaryEdges) {
    Mesh mesh = cube();
    mesh.triangles.pop_back();
    const MeshAnalysis r = analyze_mesh(mesh);
    EXPECT_EQ(r.boundary_edges, 3u);
    EXPECT_EQ(r.boundary_loops, 1u);
    EXPECT_FALSE(r.closed);
    EXPECT_EQ(r.genus, 0);  // a disc: V - E + F = 1 = 2 - 0 - 1
    EXPECT_FALSE(r.is_clean());
}

TEST(AnalyzeMeshTest, FlippedTriangleMisorientsItsEdges) {
    Mesh mesh = cube();
    std::swap(mesh.triangles[3][1], mesh.triangles[3][2]);
    const MeshAnalysis r = analyze_mesh(mesh);
    EXPECT_EQ(r.misoriented_edges, 3u);
    EXPECT_TRUE(r.closed);
    EXPECT_EQ(r.nonmanifold_edges, 0u);
    EXPECT_FALSE(r.is_clean());
}

TEST(AnalyzeMeshTest, ThirdTriangleOnAnEdgeIsNonManifold) {
    Mesh mesh = cube();
    mesh.vertices.push_back({0.5f, -1.0f, -1.0f});
    mesh.triangles.push_back({0, 1, 8});
    const MeshAnalysis r = analyze_mesh(mesh);
    EXPECT_EQ(r.nonmanifold_edges, 1u);
    EXPECT_EQ(r.boundary_edges, 2u);
    EXPECT_EQ(r.genus, -1);
    EXPECT_FALSE(r.is_clean());
}

TEST(AnalyzeMeshTest, ConesTouchingAtAVertexMakeItNonManifold) {
    // Two tetrahedra sharing only vertex 0: the second is the first mirrored through the origin.
    Mesh mesh = tetrahedron();
    for (int k = 1; k < 4; ++k) {
        const auto& v = mesh.vertices[k];
        mesh.vertices.push_back({-v[0], -v[1], -v[2]});
    }
    const auto mirrored = [](std::uint32_t v) { return v == 0 ? 0u : v + 3; };
    for (std::size_t i = 0; i < 4; ++i) {
        const auto t = mesh.triangles[i];
        // A point reflection reverses orientation: swap two corners to stay outward.
        mesh.triangles.push_back({mirrored(t[0]), mirrored(t[2]), mirrored(t[1])});
    }
    const MeshAnalysis r = analyze_mesh(mesh);
    EXPECT_EQ(r.nonmanifold_vertices, 1u);
    EXPECT_EQ(r.nonmanifold_edges, 0u);
    EXPECT_EQ(r.misoriented_edges, 0u);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.outward);
    EXPECT_EQ(r.components, 1u);
    EXPECT_EQ(r.self_intersecting_pairs, 0u);  // touching at the shared vertex is not crossing
    EXPECT_FALSE(r.is_clean());
}

TEST(AnalyzeMeshTest, CrossingTrianglesIntersect) {
    const Mesh mesh = test::triangle_soup({{{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}}, {{{0.5f, 0.5f, -1}, {0.5f, 0.5f, 1}, {3, 3, 0}}}});
    const MeshAnalysis r = analyze_mesh(mesh);
    EXPECT_EQ(r.self_intersecting_pairs, 1u);
    EXPECT_EQ(r.components, 2u);
}

TEST(AnalyzeMeshTest, DuplicatedFaceIsCaught) {
    Mesh mesh = cube();
    mesh.triangles.push_back(mesh.triangles[5]);
    const MeshAnalysis r = analyze_mesh(mesh);
    EXPECT_EQ(r.self_intersecting_pairs, 1u);
    EXPECT_EQ(r.nonmanifold_edges, 3u);
    EXPECT_EQ(r.misoriented_edges, 3u);
    EXPECT_FALSE(r.is_clean());
}

TEST(AnalyzeMeshTest, DegenerateFacesAreCountedBothWays) {
    Mesh mesh = cube();
    mesh.vertices.push_back({0.5f, 0, 0});  // on the edge from vertex 0 to vertex 1
    mesh.triangles.push_back({0, 8, 1});    // zero area, distinct indices
    mesh.triangles.push_back({2, 2, 3});    // repeated vertex
    const MeshAnalysis r = analyze_mesh(mesh);
    EXPECT_EQ(r.zero_area_faces, 1u);
    EXPECT_EQ(r.repeated_vertex_faces, 1u);
    EXPECT_EQ(r.degenerate_faces, 2u);
    EXPECT_NEAR(r.min_angle_deg, 45.0, 1e-9);  // degenerate faces are left out of the angles
    EXPECT_FALSE(r.is_clean());
}

TEST(AnalyzeMeshTest, SmallAnglesAreMeasured) {
    // One sliver with a 5.71 degree angle (atan(0.1)) among otherwise fine triangles.
    const Mesh mesh = test::triangle_soup({{{{0, 0, 0}, {10, 0, 0}, {10, 1, 0}}}});
    const MeshAnalysis r = analyze_mesh(mesh);
    EXPECT_NEAR(r.min_angle_deg, std::atan(0.1) * 180 / M_PI, 1e-6);
    EXPECT_NEAR(r.small_angle_share, 1.0 / 3, 1e-12);
}

TEST(AnalyzeMeshTest, EmptyMeshIsNotClean) {
    const MeshAnalysis r = analyze_mesh(Mesh{});
    EXPECT_EQ(r.triangles, 0u);
    EXPECT_FALSE(r.is_clean());
}

TEST(AnalyzeMeshTest, OutOfRangeIndexThrows) {
    Mesh mesh = tetrahedron();
    mesh.triangles[0][2] = 17;
    EXPECT_THROW(analyze_mesh(mesh), Error);
    EXPECT_THROW(find_self_intersections(mesh), Error);
}

TEST(AnalyzeMeshTest, UnreferencedVerticesAreCountedNotUsed) {
    Mesh mesh = tetrahedron();
    mesh.vertices.push_back({5, 5, 5});
    const MeshAnalysis r = analyze_mesh(mesh);
    EXPECT_EQ(r.unreferenced_vertices, 1u);
    EXPECT_EQ(r.euler_characteristic, 2);
    EXPECT_TRUE(r.is_clean());
}

}  // namespace
}  // namespace vdbmesh
