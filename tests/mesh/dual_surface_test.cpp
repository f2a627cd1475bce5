// The dual surface (MeshMethod::dual, experimental; issue 29, item 1, route 2): CGAL judges its
// meshes (cgal_judge.h: manifold, closed, outward, no degenerate faces, no self-intersection) on
// noise, the phantoms, the quick start's sample and the real scans; it has as many triangles
// as crossed grid edges make quads; the same bytes for one and two threads; and on the sample
// its angles and distance beat volumeToMesh at adaptivity 0 (the figure), measured by
// analysis.h and compare.h, not by the mesher.

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <iostream>
#include <string>

#include "cgal_judge.h"
#include "mesh_checks.h"
#include "phantom_grid.h"
#include "shared_scan.h"
#include "test_data.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/compare.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/phantom.h"
#include "vdbmesh/read.h"

namespace vdbmesh {
namespace {

using test::mesh_options;

/// A smooth random field on an n^3 grid, values about 0..1: a sum of a few plane waves (the
/// configurations noise makes: ambiguous faces, thin sheets, specks, tunnels).
openvdb::FloatGrid::Ptr noise_grid(int n, unsigned seed) {
    std::array<std::array<double, 4>, 6> waves;
    unsigned state = seed * 2654435761u + 1;
    const auto next = [&] {
        state = state * 1664525u + 1013904223u;
        return double(state >> 8) / double(1u << 24);
    };
    for (auto& w : waves) w = {next() - 0.5, next() - 0.5, next() - 0.5, next() * 6.28};
    return test::make_grid(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(n - 1)), [&](int x, int y, int z) {
        double sum = 0;
        for (const auto& w : waves) sum += std::sin(1.7 * (w[0] * x + w[1] * y + w[2] * z) + w[3]);
        return float(0.5 + sum / 6);
    }, 0.0f);
}

Mesh dual_mesh(const openvdb::FloatGrid& grid, double iso) { return mesh_grid(grid, mesh_options(MeshMethod::dual, iso)).mesh; }

void expect_clean(const Mesh& mesh, const std::string& what) {
    const test::CgalVerdict verdict = test::judge_with_cgal(mesh);
    const MeshAnalysis a = analyze_mesh(mesh);
    EXPECT_TRUE(verdict.clean()) << what << ", " << mesh.triangles.size() << " triangles: " << verdict.describe() << "; vdbmesh check: "
                                 << a.nonmanifold_edges << " non-manifold edges, " << a.nonmanifold_vertices << " non-manifold vertices, "
                                 << a.boundary_edges << " boundary edges, " << a.self_intersecting_pairs << " self-intersecting pairs";
}

TEST(DualSurfaceTest, NoiseIsCleanWithAQuadPerCrossedEdge) {
    for (unsigned seed = 1; seed <= 4; ++seed) {
        const auto grid = noise_grid(32, seed);
        for (double iso : {0.4, 0.5, 0.6}) {
            const Mesh mesh = dual_mesh(*grid, iso);
            const Mesh mc = mesh_grid(*grid, mesh_options(MeshMethod::mc, iso)).mesh;
            const std::string what = "seed " + std::to_string(seed) + " iso " + std::to_string(iso);
            expect_clean(mesh, what);
            // A quad per crossed grid edge, where Marching Cubes has a vertex.
            EXPECT_EQ(mesh.triangles.size(), 2 * mc.vertices.size()) << what;
        }
    }
}

TEST(DualSurfaceTest, PhantomsAreClean) {
    for (const std::string& name : phantom_preset_names()) {
        expect_clean(dual_mesh(*test::phantom_scan_grid(phantom_preset(name, {96, 96, 96})), 0.5), name);
        PhantomSpec noisy = phantom_preset(name, {96, 96, 96});
        noisy.noise_sigma = 0.02;  // +-0.2 voxel, like a scan's (phantom_guarantees_test.cpp)
        expect_clean(dual_mesh(*test::phantom_scan_grid(noisy), 0.5), name + " noisy");
    }
}

TEST(DualSurfaceTest, SameBytesWithOneOrTwoThreads) {
    const auto grid = noise_grid(40, 9);
    Mesh one, two;
    tbb::task_arena(1).execute([&] { one = dual_mesh(*grid, 0.5); });
    tbb::task_arena(2).execute([&] { two = dual_mesh(*grid, 0.5); });
    EXPECT_EQ(one.vertices, two.vertices);
    EXPECT_EQ(one.triangles, two.triangles);
}

TEST(DualSurfaceTest, RefusesAnOpenBoundary) {
    const auto grid = noise_grid(16, 1);
    MeshOptions options = mesh_options(MeshMethod::dual, 0.5);
    options.open_boundary = true;
    EXPECT_THROW(mesh_grid(*grid, options), UsageError);
}

/// The quick start's sample (testdata/sphere_phantom.nii.gz at 0.5) converted as `vdbmesh mesh` reads it.
openvdb::FloatGrid::Ptr sample_grid() {
    ConvertOptions convert;
    convert.iso = 0.5;
    return convert_to_grid(*open_volume(test::testdata("sphere_phantom.nii.gz")), convert);
}

// The figure on the sample: volumeToMesh at 0 has no angle under 10 degrees and is
// 0.049 voxel from the trilinear isosurface (compare's two-sided Hausdorff estimate); the dual
// surface must have no more such angles and no larger distance, with no more triangles.
TEST(DualSurfaceTest, SampleBeatsVolumeToMeshAtZero) {
    const auto grid = sample_grid();
    const Mesh dual = dual_mesh(*grid, 0.5);
    const Mesh openvdb = mesh_grid(*grid, mesh_options(MeshMethod::openvdb, 0.5)).mesh;
    expect_clean(dual, "sample");
    const TrueSurface truth(*grid, 0.5, Inside::above, AccuracyOptions{});
    const double dual_distance = truth.measure(dual).distance.hausdorff, openvdb_distance = truth.measure(openvdb).distance.hausdorff;
    const double dual_angles = analyze_mesh(dual).small_angle_share, openvdb_angles = analyze_mesh(openvdb).small_angle_share;
    std::cout << "[ figures  ] sample: dual " << dual.triangles.size() << " triangles, Hausdorff " << dual_distance << ", angles < 10 deg "
              << 100 * dual_angles << "%; volumeToMesh " << openvdb.triangles.size() << ", " << openvdb_distance << ", " << 100 * openvdb_angles << "%\n";
    EXPECT_LE(dual.triangles.size(), openvdb.triangles.size());
    EXPECT_LE(dual_angles, openvdb_angles);
    EXPECT_LE(dual_distance, openvdb_distance);
}

class DualSurfaceScanTest : public ::testing::TestWithParam<test::SharedScan> {
protected:
    tbb::global_control threads_{tbb::global_control::max_allowed_parallelism, 2};
};

// The engine and the walnut by default; the CThead and the bunny with VDBMESH_FULL=1.
TEST_P(DualSurfaceScanTest, IsClean) {
    const test::SharedScan& scan = GetParam();
    if (!test::full_run() && scan.name != "EngineNifti" && scan.name != "WalnutOpenQVis") GTEST_SKIP() << "VDBMESH_FULL=1 judges it";
    openvdb::FloatGrid::Ptr grid;
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan, grid));
    if (!grid) return;
    expect_clean(dual_mesh(*grid, scan.iso), scan.name);
}

INSTANTIATE_TEST_SUITE_P(SharedData, DualSurfaceScanTest,
                         ::testing::Values(test::shared_scan("EngineNifti"), test::shared_scan("WalnutOpenQVis"), test::shared_scan("CThead"),
                                           test::shared_scan("BunnyCt")),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace vdbmesh
