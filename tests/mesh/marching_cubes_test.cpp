// Marching Cubes on small analytic grids: closed, manifold, outward, accurate, free of degenerate
// triangles on integer data, independent of the thread count, closed or open at the scan box.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <random>

#include "mesh/marching_cubes.h"
#include "mesh_checks.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/grid.h"

namespace vdbmesh::test {
namespace {

void expect_closed_manifold(const Mesh& mesh) {
    ASSERT_FALSE(mesh.triangles.empty());
    const MeshAnalysis report = analyze_mesh(mesh);
    EXPECT_TRUE(report.closed);
    EXPECT_EQ(report.nonmanifold_edges, 0u);
    EXPECT_EQ(report.nonmanifold_vertices, 0u);
    EXPECT_EQ(report.misoriented_edges, 0u);
    EXPECT_EQ(report.unreferenced_vertices, 0u);
    EXPECT_EQ(report.degenerate_faces, 0u);
    EXPECT_EQ(report.self_intersecting_pairs, 0u);
    EXPECT_EQ(coincident_vertices(mesh), 0u);
}

/// The volume inside Marching Cubes' surface around a box of n[0] x n[1] x n[2] inside samples
/// whose faces sit @a d beyond the last samples: the full box less, along each of its 12 edges,
/// a right prism of legs d per unit length (the cells there cut the corner diagonally) and, at
/// each of the 8 corners, 5/6 of the d^3 corner cube (the corner cell keeps a tetrahedron).
double mc_box_volume(const std::array<int, 3>& n, double d) {
    double volume = 1, edges = 0;
    for (int a = 0; a < 3; ++a) {
        volume *= n[a] - 1 + 2 * d;
        edges += 4 * (n[a] - 1);
    }
    return volume - edges * d * d / 2 - 8 * d * d * d * 5 / 6;
}

void set_scan_box(openvdb::FloatGrid& grid, const openvdb::Coord& min, const openvdb::Coord& max) {
    grid.insertMeta(kMetaScanMin, openvdb::Vec3IMetadata(min.asVec3i()));
    grid.insertMeta(kMetaScanMax, openvdb::Vec3IMetadata(max.asVec3i()));
}

TEST(MarchingCubesTest, BallIsClosedOutwardAndHasTheRightVolume) {
    const double radius = 10;
    auto grid = make_ball(radius, {0.3, 0.2, 0.1});
    const Mesh mesh = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 0.0));
    expect_closed_manifold(mesh);
    // The field is the exact signed distance, so the vertices lie within h^2 / (2 R) = 0.05
    // voxels of the sphere and the flat triangles (edges up to sqrt(2) voxels) sag at most
    // l^2 / (8 R) = 0.025 more: the volume is off by at most area x 0.075; allow area x 0.1.
    const double exact_volume = 4.0 / 3.0 * kPi * radius * radius * radius;
    const double exact_area = 4 * kPi * radius * radius;
    EXPECT_NEAR(signed_volume(mesh), exact_volume, 0.1 * exact_area);
    EXPECT_NEAR(analyze_mesh(mesh).area, exact_area, 0.05 * exact_area);
}

TEST(MarchingCubesTest, InsideBelowMeshesTheSameObjectOutward) {
    auto grid = make_ball(6, {0.5, 0.25, 0});
    const Mesh above = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 0.0));
    for (auto it = grid->beginValueOn(); it; ++it) it.setValue(-*it);
    grid->tree().root().setBackground(-grid->background(), true);
    const Mesh below = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 0.0, Inside::below));
    expect_closed_manifold(below);
    EXPECT_EQ(below.triangles.size(), above.triangles.size());
    EXPECT_NEAR(signed_volume(below), signed_volume(above), 1e-3);
    EXPECT_GT(signed_volume(below), 0);
}

TEST(MarchingCubesTest, WorldCoordinatesFollowTheTransform) {
    auto grid = make_ball(5, {0, 0, 0});
    const Mesh index_mesh = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 0.0));
    grid->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
    grid->transform().postTranslate(openvdb::Vec3d(10, 0, 0));
    const Mesh world_mesh = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 0.0));
    ASSERT_EQ(world_mesh.vertices.size(), index_mesh.vertices.size());
    for (std::size_t v = 0; v < index_mesh.vertices.size(); ++v) {
        EXPECT_FLOAT_EQ(world_mesh.vertices[v][0], 0.5f * index_mesh.vertices[v][0] + 10.0f);
        EXPECT_FLOAT_EQ(world_mesh.vertices[v][1], 0.5f * index_mesh.vertices[v][1]);
    }
    EXPECT_NEAR(signed_volume(world_mesh), signed_volume(index_mesh) / 8, 1e-3);
}

TEST(MarchingCubesTest, IntegerIsovalueOnIntegerSamplesGivesNoDegenerateTriangles) {
    // Random integer samples 0..2 with isovalue 1: a third of the samples sit exactly on the
    // isovalue, and every corner configuration occurs.
    std::mt19937 random(12345);
    std::uniform_int_distribution<int> value(0, 2);
    auto grid = make_grid(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(23)),
                          [&](int, int, int) { return float(value(random)); }, 0.0f);
    const Mesh mesh = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 1.0));
    EXPECT_GT(mesh.triangles.size(), 5000u);
    expect_closed_manifold(mesh);
    EXPECT_GT(signed_volume(mesh), 0);
    // Every vertex lies on a grid edge (two integer coordinates) and keeps kCrossingMargin
    // (1e-3 voxels) away from its samples.
    for (const auto& v : mesh.vertices) {
        int on_lattice = 0;
        double off_sample = 1;
        for (float c : v) {
            const double fraction = std::abs(double(c) - std::round(double(c)));
            if (fraction == 0) ++on_lattice;
            else off_sample = fraction;
        }
        EXPECT_EQ(on_lattice, 2);
        EXPECT_GT(off_sample, 0.9e-3);
    }
}

TEST(MarchingCubesTest, IntegerTentFieldWithIsovalueOnSamples) {
    // f = 10 - max(|i|, |j|, |k|): the whole shell max = 5 holds exactly the isovalue 5.
    auto grid = make_grid(openvdb::CoordBBox(openvdb::Coord(-9), openvdb::Coord(9)), [](int i, int j, int k) {
        return float(10 - std::max({std::abs(i), std::abs(j), std::abs(k)}));
    }, 0.0f);
    const Mesh mesh = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 5.0));
    expect_closed_manifold(mesh);
    // Inside: max < 5, samples -4..4; the crossings are clamped 1e-3 short of the shell at 5.
    EXPECT_NEAR(signed_volume(mesh), mc_box_volume({9, 9, 9}, 1 - 1e-3), 1e-3);
}

TEST(MarchingCubesTest, SameBytesWithOneAndTwoThreads) {
    auto grid = make_ball(20, {0.1, 0.7, 0.3});
    Mesh one, two;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 0.0));
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        two = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 0.0));
    }
    ASSERT_GT(one.triangles.size(), 10000u);
    EXPECT_EQ(one.vertices, two.vertices);
    EXPECT_EQ(one.triangles, two.triangles);
}

TEST(MarchingCubesTest, TilesOfBothLevelsAreMeshed) {
    // A 128^3 tile and a 16 x 8 x 8 box made of two 8^3 tiles; no leaf at all.
    auto grid = openvdb::FloatGrid::create(-1.0f);
    grid->tree().fill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(127)), 1.0f, true);
    grid->tree().fill(openvdb::CoordBBox(openvdb::Coord(512, 0, 0), openvdb::Coord(527, 7, 7)), 1.0f, true);
    ASSERT_EQ(grid->tree().leafCount(), 0u);
    const Mesh mesh = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 0.0));
    expect_closed_manifold(mesh);
    // Values +-1 around iso 0: faces half a voxel beyond the samples. Float coordinates up
    // to 528 (exact multiples of 1/2) sum to the volume with errors far below 0.01.
    EXPECT_NEAR(signed_volume(mesh), mc_box_volume({128, 128, 128}, 0.5) + mc_box_volume({16, 8, 8}, 0.5), 0.01);
}

TEST(MarchingCubesTest, ScanBoxClosesTheCutObject) {
    // A cube of samples -10..10 cut by the scan box at 5 on every axis.
    auto grid = make_grid(openvdb::CoordBBox(openvdb::Coord(-12), openvdb::Coord(12)), [](int i, int j, int k) {
        return std::max({std::abs(i), std::abs(j), std::abs(k)}) <= 10 ? 1.0f : -1.0f;
    }, -1.0f);
    set_scan_box(*grid, openvdb::Coord(-12), openvdb::Coord(5));
    const Mesh mesh = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 0.0));
    expect_closed_manifold(mesh);
    // Samples -10..5 inside: faces at -10.5 and, half a voxel beyond the box, at 5.5.
    EXPECT_NEAR(signed_volume(mesh), mc_box_volume({16, 16, 16}, 0.5), 1e-3);
    for (const auto& v : mesh.vertices) {
        for (float c : v) EXPECT_LE(c, 5.5f);
    }
}

TEST(MarchingCubesTest, OpenBoundaryLeavesTheCutOpen) {
    auto grid = make_grid(openvdb::CoordBBox(openvdb::Coord(-12), openvdb::Coord(12)), [](int i, int j, int k) {
        return std::max({std::abs(i), std::abs(j), std::abs(k)}) <= 10 ? 1.0f : -1.0f;
    }, -1.0f);
    set_scan_box(*grid, openvdb::Coord(-12), openvdb::Coord(5));
    MeshOptions options = mesh_options(MeshMethod::mc, 0.0);
    options.open_boundary = true;
    const Mesh mesh = detail::marching_cubes(*grid, options);
    const MeshAnalysis report = analyze_mesh(mesh);
    // The three cut faces leave one boundary loop, on the planes x, y or z = 5.
    EXPECT_EQ(report.boundary_loops, 1u);
    EXPECT_GT(report.boundary_edges, 3u * 15);
    EXPECT_EQ(report.nonmanifold_edges, 0u);
    EXPECT_EQ(report.misoriented_edges, 0u);
    EXPECT_EQ(report.degenerate_faces, 0u);
    EXPECT_EQ(report.unreferenced_vertices, 0u);
    for (const auto& v : mesh.vertices) {
        for (float c : v) EXPECT_LE(c, 5.0f);
    }
}

TEST(MarchingCubesTest, WithoutScanBoxTheGridValuesRule) {
    // Background inside (above the isovalue) and no box: the surface is the one around the
    // outside-valued voxels, oriented towards them (negative volume, a cavity).
    auto grid = make_grid(openvdb::CoordBBox(openvdb::Coord(-3), openvdb::Coord(3)), [](int i, int j, int k) {
        return std::max({std::abs(i), std::abs(j), std::abs(k)}) <= 1 ? -1.0f : 1.0f;
    }, 1.0f);
    const Mesh mesh = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 0.0));
    expect_closed_manifold(mesh);
    EXPECT_LT(signed_volume(mesh), 0);
}

TEST(MarchingCubesTest, EmptyWhenNothingCrosses) {
    auto grid = make_grid(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(9)), [](int, int, int) { return 0.0f; }, 0.0f);
    EXPECT_TRUE(detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 0.5)).triangles.empty());
    EXPECT_TRUE(detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, -0.5, Inside::below)).vertices.empty());
}

}  // namespace
}  // namespace vdbmesh::test
