// Issue 3, point 6 (and issue 9, point 5): at every --error, the DMC and MC meshes of every real
// volume of the shared data (../shared/data) must be clean as an independent judge sees them:
// CGAL's Polygon_mesh_processing (cgal_judge.h: manifold, closed, bounding a volume outward, no
// degenerate faces, no self-intersection), not analyze_mesh(), from which DMC's own checks are
// built; `vdbmesh check`'s figures are printed beside it. The analytic phantoms of the other mesher tests do not exercise
// what real scans do (noise, thin walls, objects touching the scan's border, tiny components),
// so each scan is converted once at its known-good isovalue (those of the per-scan table of
// bench/README.md) and meshed with DMC at error 0 and 0.25 and with Marching Cubes: every mesh
// must be clean. Each failure message gives the figures of `vdbmesh check`.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <array>
#include <cstdint>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "cgal_judge.h"
#include "same_triangles.h"
#include "shared_scan.h"
#include "test_data.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/compare.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh {
namespace {

using test::SharedScan;


/// The meshers of the guarantee: DMC at both --error values and Marching Cubes.
struct Method {
    const char* label;
    MeshMethod method;
    double error;
};
/// Points sampled on each mesh for the distance between the meshes at error 0.25 and 0.
constexpr std::size_t kDistanceSamples = 100000;
/// Twice the error (both checks' tolerance), plus half a voxel for points inside triangles,
/// which neither check samples. Measured: 0.47 (nucleon) to 0.96 voxel (CThead); the bunny
/// CT was at 2.4 before the coverage check, 3.6 before the octree kept enclosed components.
constexpr double kHausdorffBound = 1.0;
/// Merging must pay: at error 0.25 DMC keeps 33% (engine) to 97.4% (the SPM T1 MRIs, whose
/// surfaces are noise-bound) of the error-0 triangles; a DMC that returned Marching Cubes
/// keeps 100% and fails.
constexpr double kMaxTriangleShare = 0.98;
/// Above this many Marching Cubes triangles, the DC error-0 mesh is judged with VDBMESH_FULL=1 only.
constexpr std::size_t kQuickErrorZeroTriangles = 1000000;

const std::array<Method, 3> kMethods = {{
    {"dmc --error 0", MeshMethod::dmc, 0.0},
    {"dmc --error 0.25", MeshMethod::dmc, 0.25},
    {"mc", MeshMethod::mc, 0.0},
}};

/// The figures `vdbmesh check` prints that tell why a mesh is not clean.
std::string describe(const MeshAnalysis& r) {
    std::ostringstream out;
    out << r.triangles << " triangles, " << r.self_intersecting_pairs << " self-intersecting pairs, "
        << r.boundary_edges << " boundary edges, " << r.nonmanifold_edges << " non-manifold edges, "
        << r.nonmanifold_vertices << " non-manifold vertices, " << r.misoriented_edges << " misoriented edges, "
        << r.degenerate_faces << " degenerate faces, volume " << r.volume << (r.outward ? " (outward)" : " (inward)");
    return out.str();
}

/// The scan's mesh by @a method at @a error (world space).
Mesh mesh_scan(const openvdb::FloatGrid& grid, const SharedScan& scan, MeshMethod method, double error = 0) {
    MeshOptions options;
    options.method = method;
    options.error = error;
    options.iso = scan.iso;
    return mesh_grid(grid, options).mesh;
}

class RealScanGuaranteesTest : public ::testing::TestWithParam<SharedScan> {
protected:
    // The two cores the suite is budgeted for; the meshes do not depend on it.
    tbb::global_control threads_{tbb::global_control::max_allowed_parallelism, 2};
};

TEST_P(RealScanGuaranteesTest, DmcAndMcMeshesAreClean) {
    const SharedScan& scan = GetParam();
    openvdb::FloatGrid::Ptr grid;
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan, grid));
    if (!grid) return;  // skipped: the shared data is missing

    std::vector<MeshAnalysis> reports;
    std::vector<Mesh> meshes;
    for (const Method& method : kMethods) {
        meshes.push_back(mesh_scan(*grid, scan, method.method, method.error));
        reports.push_back(analyze_mesh(meshes.back()));
        std::cout << "[ figures  ] " << scan.name << " " << method.label << ": " << describe(reports.back()) << "\n";
    }
    // DMC at error 0 is Marching Cubes to the byte, so CGAL (the suite's slowest part) judges
    // the Marching Cubes mesh for both.
    EXPECT_TRUE(test::same_triangles(meshes[0], meshes[2]))
        << scan.name << ": DMC at error 0 differs from Marching Cubes";
    for (std::size_t m : {std::size_t(1), std::size_t(2)}) {
        const test::CgalVerdict verdict = test::judge_with_cgal(meshes[m]);
        EXPECT_TRUE(verdict.clean()) << scan.name << " at iso " << scan.iso << ", " << kMethods[m].label
                                     << ": not clean: " << verdict.describe() << "; vdbmesh check: " << describe(reports[m]);
    }
    const std::vector<Mesh> dmc_meshes = {to_index_space(meshes[0], *grid), to_index_space(meshes[1], *grid)};
    EXPECT_LE(double(reports[1].triangles), kMaxTriangleShare * double(reports[0].triangles))
        << scan.name << ": DMC at error 0.25 must have fewer triangles than at error 0";
    // Merging must not erase Marching Cubes' surfaces: specks of noise at the threshold are
    // components of their own (the bunny CT's error-0 mesh has 1,219). Specks that straddle a
    // leaf's sample block are not protected (dmc_enclosed_components.h): up to 2% may go (the
    // bunny lost 32 before the octree kept enclosed components, 4 since; headsq 3 of 258).
    EXPECT_GE(reports[1].components * 100, reports[0].components * 98) << scan.name << ": components at error 0.25 vs 0";
    // --error bounds the distance both ways: the self-check holds the triangles' centroids
    // within twice the error of the isosurface, the coverage check the crossings of the
    // isosurface with the grid edges (the error-0 mesh's vertices) within twice the error of
    // the mesh; points between those may stray a little farther.
    const DistanceReport distance = mesh_distance(dmc_meshes[1], dmc_meshes[0], kDistanceSamples);
    std::cout << "[ figures  ] " << scan.name << " dmc --error 0.25 vs 0: two-sided Hausdorff " << distance.hausdorff << " voxels\n";
    EXPECT_LE(distance.hausdorff, kHausdorffBound) << scan.name;
}

// Intersection-free DC (issue 9, point 2): clean by construction at every error, so no check
// runs; CGAL judges it. It keeps every Marching Cubes component (a merged cell holds one disk of
// surface). At error 0 it is the dual mesh (issue 29): a vertex per simple unit cell on the
// trilinear isosurface, Marching Cubes in the cells with two sheets or an ambiguous face.
TEST_P(RealScanGuaranteesTest, DcMeshesAreCleanAndKeepEveryComponent) {
    const SharedScan& scan = GetParam();
    openvdb::FloatGrid::Ptr grid;
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan, grid));
    if (!grid) return;  // skipped: the shared data is missing
    const Mesh mc = mesh_scan(*grid, scan, MeshMethod::mc);
    const MeshAnalysis mc_report = analyze_mesh(mc);
    for (double error : {0.0, 0.25, 1.0}) {
        // CGAL takes minutes on the error-0 meshes of the bunny CT and the Seg3D MR (3.1 and
        // 2.7 million triangles): those two run with VDBMESH_FULL=1.
        if (error == 0 && mc_report.triangles > kQuickErrorZeroTriangles && !test::full_run()) {
            std::cout << "[ skipped  ] " << scan.name << " dc --error 0: a long case, runs with VDBMESH_FULL=1\n";
            continue;
        }
        const Mesh dc = mesh_scan(*grid, scan, MeshMethod::dc, error);
        const MeshAnalysis report = analyze_mesh(dc);
        std::cout << "[ figures  ] " << scan.name << " dc --error " << error << ": " << describe(report) << "\n";
        const test::CgalVerdict verdict = test::judge_with_cgal(dc);
        EXPECT_TRUE(verdict.clean()) << scan.name << " dc --error " << error << ": not clean: " << verdict.describe();
        EXPECT_EQ(report.components, mc_report.components) << scan.name << " dc --error " << error;
        // Merging pays at error 1 (a DC that returned MC fails). At 0.25 the noise-bound MRIs
        // barely merge and the fans between merged and unit cells cost a little: measured
        // 98.3% of MC (headsq) to 100.8% (the SPM T1s, 132,168 of 131,160), so at most 1% more.
        // At error 0 the fans between dual and Marching Cubes cells cost more where ambiguous
        // cells are many: measured 0.2% (engine) to 19% (Seg3D MR, 2,728,812 of 2,293,400) more
        // than MC; 12% on the walnut, 9.5% on the SPM T1s.
        const double triangle_bound = error == 0 ? 1.2 : 1.01;
        EXPECT_LE(double(report.triangles), triangle_bound * double(mc_report.triangles)) << scan.name << " dc --error " << error;
        if (error == 1.0) {
            EXPECT_LE(double(report.triangles), kMaxTriangleShare * double(mc_report.triangles)) << scan.name << " dc --error 1";
        }
        // Crossings kept min(E, 0.25) from the samples and face points chosen for their angles
        // (ifc_polygons.cpp): fewer angles under 10 degrees than Marching Cubes on the same
        // grid (before, DC had more: bunny at error 1, 3.88% against 3.21%).
        std::cout << "[ figures  ] " << scan.name << " dc --error " << error << ": angles under 10 degrees " << report.small_angle_share
                  << " (MC " << mc_report.small_angle_share << ")\n";
        EXPECT_LT(report.small_angle_share, mc_report.small_angle_share) << scan.name << " dc --error " << error;
        const DistanceReport distance = mesh_distance(to_index_space(dc, *grid), to_index_space(mc, *grid), kDistanceSamples);
        std::cout << "[ figures  ] " << scan.name << " dc --error " << error << " vs MC: two-sided Hausdorff "
                  << distance.hausdorff << " voxels\n";
        // Twice the error (the vertex is within the error of every tangent plane in its cell),
        // plus half a voxel for points between samples. At error 0 the two meshes are different
        // approximations of the trilinear isosurface (MC's flat triangles across its curved
        // cells, the dual vertices on it): measured 0.29 (nucleon) to 0.56 voxel (SPM2 T1), so
        // within a voxel.
        EXPECT_LE(distance.hausdorff, error == 0 ? 1.0 : 2 * error + 0.5) << scan.name << " dc --error " << error;
    }
}

// A polygon round a crossed edge drops the edge's crossing, so it must pass within the error of
// it (ifc_polygons.cpp, polygon_near()). On the CThead a thin wall (0.2 voxel) ends at the bottom
// slice by (174, 224, 0); at --error 1 the polygon of the four cells round its lowest crossed
// edge cut 1.72 voxels off its tip (0.85 since). The Marching Cubes vertices there must lie
// within the error of the DC mesh, plus the 0.25 voxel the mesh's crossings are moved along
// their edges at that error (ifc_crossing_margin()).
TEST(DcPolygonAccuracyTest, CtheadThinWallKeepsItsTip) {
    const SharedScan& scan = test::shared_scan("CThead");
    openvdb::FloatGrid::Ptr grid;
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan, grid));
    if (!grid) return;  // skipped: the shared data is missing
    constexpr double kError = 1.0;
    const Mesh mc = to_index_space(mesh_scan(*grid, scan, MeshMethod::mc), *grid);
    const Mesh dc = to_index_space(mesh_scan(*grid, scan, MeshMethod::dc, kError), *grid);
    std::vector<std::uint32_t> all(dc.triangles.size());
    for (std::uint32_t t = 0; t < all.size(); ++t) all[t] = t;
    const detail::TriangleBvh tree(dc, all);
    const std::array<double, 3> tip = {174, 224, 0.5};
    double farthest = 0;
    int near_tip = 0;
    for (const auto& v : mc.vertices) {
        if (std::abs(v[0] - tip[0]) > 3 || std::abs(v[1] - tip[1]) > 3 || std::abs(v[2] - tip[2]) > 3) continue;
        ++near_tip;
        farthest = std::max(farthest, std::sqrt(tree.closest_point({v[0], v[1], v[2]}).distance_squared));
    }
    ASSERT_GT(near_tip, 0) << "no Marching Cubes vertex by the wall's tip: the scan or its frame changed";
    std::cout << "[ figures  ] CThead dc --error 1: the wall's tip " << farthest << " voxels from the mesh\n";
    EXPECT_LE(farthest, kError + 0.25);
}

INSTANTIATE_TEST_SUITE_P(SharedData, RealScanGuaranteesTest, ::testing::ValuesIn(test::shared_scans()),
                         [](const ::testing::TestParamInfo<SharedScan>& info) { return info.param.name; });

}  // namespace
}  // namespace vdbmesh
