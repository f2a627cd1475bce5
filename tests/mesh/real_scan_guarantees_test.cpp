// Issue 3, point 6 (and issue 9, point 5): the meshes of every real volume of the shared data
// (../shared/data), Marching Cubes and intersection-free DC at every --error, must be clean as an
// independent judge sees them: CGAL's Polygon_mesh_processing (cgal_judge.h: manifold, closed,
// bounding a volume outward, no degenerate faces, no self-intersection), not analyze_mesh();
// `vdbmesh check`'s figures are printed beside it. The analytic phantoms of the other mesher
// tests do not exercise what real scans do (noise, thin walls, objects touching the scan's
// border, tiny components), so each scan is converted once at its known-good isovalue (those of
// the per-scan table of bench/README.md). Each failure message gives the figures of `vdbmesh check`.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "cgal_judge.h"
#include "shared_scan.h"
#include "test_data.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/compare.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh {
namespace {

using test::SharedScan;

/// Points sampled on each mesh for the distance between the DC and the MC meshes.
constexpr std::size_t kDistanceSamples = 100000;
/// Merging must pay: at error 1 DC keeps at most this share of Marching Cubes' triangles; a DC
/// that returned Marching Cubes keeps 100% and fails.
constexpr double kMaxTriangleShare = 0.98;

/// At error 0 (the dual mesh: a vertex per unit cell whose surface is one disk, Marching Cubes in
/// the others) at most this share of Marching Cubes' triangles: where a polygon round a crossed
/// edge fails its flip test, and round the Marching Cubes cells, the fans add triangles.
/// Measured (session 22): engine 1.002, CThead 1.062, walnut 1.122.
constexpr double kErrorZeroTriangleShare = 1.15;

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

/// The scans whose whole meshes are the suite's costliest to judge (a fresh clone's suite:
/// Seg3dMrNifti 200 s, Marching Cubes 2,293,404 triangles and DC at 0.25 2,095,678, the noise
/// of the MRI barely merging; BunnyCt 81 s, Marching Cubes 3,022,504): by default CGAL judges
/// their DC mesh at error 1 only, and the other scans judge Marching Cubes and DC at 0.25, the
/// same code. VDBMESH_FULL=1 judges every setting on every scan.
bool judges_every_setting(const SharedScan& scan) {
    return test::full_run() || (scan.name != "Seg3dMrNifti" && scan.name != "BunnyCt");
}

class RealScanGuaranteesTest : public ::testing::TestWithParam<SharedScan> {
protected:
    // The two cores the suite is budgeted for; the meshes do not depend on it.
    tbb::global_control threads_{tbb::global_control::max_allowed_parallelism, 2};
};

// Intersection-free DC (issue 9, point 2): clean by construction at every error, so no check
// runs; CGAL judges it, and Marching Cubes. DC keeps every Marching Cubes component (a merged
// cell holds one disk of surface; at error 0, the dual mesh, a unit cell one disk). On the two
// costliest scans the default suite judges DC at error 1 only (judges_every_setting()); every
// count below is still asserted there.
TEST_P(RealScanGuaranteesTest, DcMeshesAreCleanAndKeepEveryComponent) {
    const SharedScan& scan = GetParam();
    openvdb::FloatGrid::Ptr grid;
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan, grid));
    if (!grid) return;  // skipped: the shared data is missing
    const bool every_setting = judges_every_setting(scan);
    const Mesh mc = mesh_scan(*grid, scan, MeshMethod::mc);
    const MeshAnalysis mc_report = analyze_mesh(mc);
    std::cout << "[ figures  ] " << scan.name << " mc: " << describe(mc_report) << "\n";
    if (every_setting) {
        const test::CgalVerdict mc_verdict = test::judge_with_cgal(mc);
        EXPECT_TRUE(mc_verdict.clean()) << scan.name << " at iso " << scan.iso << ", mc: not clean: " << mc_verdict.describe()
                                        << "; vdbmesh check: " << describe(mc_report);
    }
    for (double error : every_setting ? std::vector<double>{0.0, 0.25, 1.0} : std::vector<double>{1.0}) {
        const Mesh dc = mesh_scan(*grid, scan, MeshMethod::dc, error);
        const MeshAnalysis report = analyze_mesh(dc);
        std::cout << "[ figures  ] " << scan.name << " dc --error " << error << ": " << describe(report) << "\n";
        const test::CgalVerdict verdict = test::judge_with_cgal(dc);
        EXPECT_TRUE(verdict.clean()) << scan.name << " dc --error " << error << ": not clean: " << verdict.describe();
        EXPECT_EQ(report.components, mc_report.components) << scan.name << " dc --error " << error;
        // Merging pays at error 1 (a DC that returned MC fails). At 0.25 the noise-bound MRIs
        // barely merge and the fans between merged and unit cells cost a little: measured
        // 98.3% of MC (headsq) to 100.8% (the SPM T1s, 132,168 of 131,160), so at most 1% more.
        const double most = error == 0 ? kErrorZeroTriangleShare : 1.01;
        EXPECT_LE(double(report.triangles), most * double(mc_report.triangles)) << scan.name << " dc --error " << error;
        if (error == 1.0) {
            EXPECT_LE(double(report.triangles), kMaxTriangleShare * double(mc_report.triangles)) << scan.name << " dc --error 1";
        }
        // Crossings kept min(E, 0.25) from the samples and face points chosen for their angles
        // (dc_polygons.cpp): fewer angles under 10 degrees than Marching Cubes on the same
        // grid (before, DC had more: bunny at error 1, 3.88% against 3.21%).
        std::cout << "[ figures  ] " << scan.name << " dc --error " << error << ": angles under 10 degrees " << report.small_angle_share
                  << " (MC " << mc_report.small_angle_share << ")\n";
        EXPECT_LT(report.small_angle_share, mc_report.small_angle_share) << scan.name << " dc --error " << error;
        const DistanceReport distance = mesh_distance(to_index_space(dc, *grid), to_index_space(mc, *grid), kDistanceSamples);
        std::cout << "[ figures  ] " << scan.name << " dc --error " << error << " vs MC: two-sided Hausdorff "
                  << distance.hausdorff << " voxels\n";
        // Twice the error (the vertex is within the error of every tangent plane in its cell),
        // plus half a voxel for points between samples. At error 0 (the dual mesh) a cell's
        // diagonal: both meshes cross the same unit cells and stay inside them (measured engine
        // 0.41, CThead 0.85, walnut 0.99 voxel, session 22).
        const double bound = error == 0 ? std::sqrt(3.0) : 2 * error + 0.5;
        EXPECT_LE(distance.hausdorff, bound) << scan.name << " dc --error " << error;
    }
}

// A polygon round a crossed edge drops the edge's crossing, so it must pass within the error of
// it (dc_polygons.cpp, polygon_near()). On the CThead a thin wall (0.2 voxel) ends at the bottom
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
