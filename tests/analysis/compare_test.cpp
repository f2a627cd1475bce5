// compare.h: distance to the trilinear isosurface, accuracy against exact phantom surfaces,
// compare_meshers() on a small phantom.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "phantom_grid.h"
#include "test_data.h"
#include "vdbmesh/compare.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/mesh_budget.h"
#include "vdbmesh/phantom.h"

namespace vdbmesh {
namespace {

using test::phantom_scan_grid;

Mesh mesh_with(const openvdb::FloatGrid& grid, MeshMethod method, double adaptivity = 0) {
    MeshOptions options;
    options.method = method;
    options.iso = 0.5;
    options.adaptivity = adaptivity;
    return mesh_grid(grid, options).mesh;
}

SignedDistance exact_distance(const PhantomSpec& spec) {
    return [spec](double x, double y, double z) { return phantom_signed_distance(spec, x, y, z); };
}

class CompareTest : public testing::Test {
protected:
    static void SetUpTestSuite() {
        sphere_ = new PhantomSpec(phantom_preset("sphere", {64, 64, 64}));  // radius 20, blur 5
        grid_holder_ = phantom_scan_grid(*sphere_);
        grid_ = grid_holder_.get();
    }
    static void TearDownTestSuite() {
        grid_holder_.reset();
        delete sphere_;
    }
    static PhantomSpec* sphere_;
    static openvdb::FloatGrid* grid_;
    static openvdb::FloatGrid::Ptr grid_holder_;
};
PhantomSpec* CompareTest::sphere_ = nullptr;
openvdb::FloatGrid* CompareTest::grid_ = nullptr;
openvdb::FloatGrid::Ptr CompareTest::grid_holder_;

TEST(IsosurfaceDistanceTest, PlaneGivesTheExactDistance) {
    // f(i, j, k) = i: the trilinear interpolant is x itself, its 2.5 isosurface the plane x = 2.5.
    auto grid = openvdb::FloatGrid::create(-100.f);
    auto accessor = grid->getAccessor();
    for (int i = -8; i < 16; ++i)
        for (int j = -8; j < 16; ++j)
            for (int k = -8; k < 16; ++k) accessor.setValue(openvdb::Coord(i, j, k), float(i));
    for (const double x : {2.5, 2.0, 3.7, 0.2, 5.9}) {
        const auto d = distance_to_trilinear_isosurface(*grid, 2.5, std::array<double, 3>{x, 1.3, 4.6});
        ASSERT_TRUE(d.has_value()) << x;
        EXPECT_NEAR(*d, std::fabs(x - 2.5), 1e-6) << x;  // Newton tolerance 1e-7 voxel
    }
    // 6.5 voxels from the plane, farther than the search radius, and the field only falls
    // towards the background elsewhere around it: no surface found.
    EXPECT_FALSE(distance_to_trilinear_isosurface(*grid, 2.5, std::array<double, 3>{-4.0, 1.3, 4.6}).has_value());
    // Past x = 15 the background (-100) makes a second sheet, at x = 15 + 12.5 / 115.
    const auto far = distance_to_trilinear_isosurface(*grid, 2.5, std::array<double, 3>{12.0, 1.3, 4.6});
    ASSERT_TRUE(far.has_value());
    EXPECT_NEAR(*far, 3.0 + 12.5 / 115.0, 1e-6);
}

TEST_F(CompareTest, McVerticesLieOnTheTrilinearIsosurface) {
    // MC puts each vertex where the linear interpolation along a grid edge crosses the
    // isovalue, which is where the trilinear interpolant (linear along edges) crosses it:
    // only float rounding of the coordinates (~64 * 2^-24 voxel) separates them.
    const Mesh mesh = to_index_space(mesh_with(*grid_, MeshMethod::mc), *grid_);
    ASSERT_GT(mesh.vertices.size(), 1000u);
    double worst = 0;
    for (const auto& v : mesh.vertices) {
        const auto d = distance_to_trilinear_isosurface(*grid_, 0.5, std::array<double, 3>{v[0], v[1], v[2]});
        ASSERT_TRUE(d.has_value());
        worst = std::max(worst, *d);
    }
    EXPECT_LT(worst, 1e-4);
}

TEST(IsosurfaceDistanceTest, McVerticesLieOnTheTrilinearIsosurfaceOfARealScan) {
    VDBMESH_SHARED_DATA(path, "nifti_engine_ct/engine.nii.gz");
    auto reader = open_volume(path);
    ConvertOptions convert;
    convert.iso = 100.5;
    const auto grid = convert_to_grid(*reader, convert);
    MeshOptions options;
    options.method = MeshMethod::mc;
    options.iso = 100.5;
    const Mesh mesh = to_index_space(mesh_grid(*grid, options).mesh, *grid);
    double worst = 0;
    for (std::size_t i = 0; i < mesh.vertices.size(); i += 97) {  // a spread subset: the full set takes long
        const auto& v = mesh.vertices[i];
        const auto d = distance_to_trilinear_isosurface(*grid, 100.5, std::array<double, 3>{v[0], v[1], v[2]});
        ASSERT_TRUE(d.has_value()) << i;
        worst = std::max(worst, *d);
    }
    EXPECT_LT(worst, 1e-3);  // float coordinates (256 * 2^-24) over gradients of a few units per voxel
}

TEST_F(CompareTest, McIsWithinFiveHundredthsOfAVoxelOfTheExactSphere) {
    // Within the blur ramp the density is linear in the signed distance, so edge crossings
    // are off the sphere only by the curvature of |x| - r along a unit edge (<= 1/(8r) =
    // 0.006 voxel at r = 20), and flat triangles of diameter <= sqrt(2) sag by d^2/(8r) =
    // 0.0125 voxel: 0.05 leaves room for float rounding and sampling.
    const TrueSurface truth(*grid_, 0.5, Inside::above, {20000, exact_distance(*sphere_)});
    const Accuracy accuracy = truth.measure(mesh_with(*grid_, MeshMethod::mc));
    EXPECT_LT(accuracy.distance.hausdorff, 0.05);
    EXPECT_GT(accuracy.distance.max_b_to_a, 0.0);  // the exact-surface samples were measured
    EXPECT_LT(accuracy.normals.mean_deg, 2.0);     // facets of a radius-20 sphere: a few degrees at most
    EXPECT_LE(accuracy.normals.mean_deg, accuracy.normals.p95_deg);
}

/// The cube [c - h, c + h]^3 with its corner (+, +, +) cut off by the plane through the points
/// @a t along its three edges from that corner: 10 vertices, 3 squares, 3 pentagons and the cut,
/// fanned into triangles turned outwards (the solid is convex).
Mesh cube_with_a_corner_cut(const std::array<double, 3>& c, double h, double t) {
    Mesh mesh;
    const auto add = [&](double x, double y, double z) {
        mesh.vertices.push_back({float(c[0] + x), float(c[1] + y), float(c[2] + z)});
    };
    for (int i = 0; i < 7; ++i) add(i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h);  // corner 7, (+, +, +), is cut
    add(h - t, h, h);  // 7: A on the x edge
    add(h, h - t, h);  // 8: B on the y edge
    add(h, h, h - t);  // 9: C on the z edge
    const std::vector<std::vector<std::uint32_t>> faces = {{0, 2, 6, 4}, {0, 1, 5, 4}, {0, 1, 3, 2}, {1, 3, 9, 8, 5},
                                                           {2, 3, 9, 7, 6}, {4, 5, 8, 7, 6}, {7, 8, 9}};
    for (const auto& face : faces) {
        for (std::size_t k = 1; k + 1 < face.size(); ++k) {
            std::array<std::uint32_t, 3> tri{face[0], face[k], face[k + 1]};
            const auto point = [&](std::uint32_t v) { return openvdb::Vec3d(mesh.vertices[v][0], mesh.vertices[v][1], mesh.vertices[v][2]); };
            const openvdb::Vec3d normal = (point(tri[1]) - point(tri[0])).cross(point(tri[2]) - point(tri[0]));
            const openvdb::Vec3d outward = point(tri[0]) - openvdb::Vec3d(c[0], c[1], c[2]);
            if (normal.dot(outward) < 0) std::swap(tri[1], tri[2]);
            mesh.triangles.push_back(tri);
        }
    }
    return mesh;
}

TEST(ExactSurfacePointsTest, ACubeWithACornerCutIsReportedAtTheCutsDistance) {
    // By hand: the cut corner is t / sqrt(3) from the cut plane (the foot of the perpendicular
    // is the cut triangle's centroid); every mesh point is at most t / 3 inside the cube (the
    // centroid again), and every other one on it. So the Hausdorff distance is t / sqrt(3),
    // reached only at the corner, which reference points drawn from a Marching Cubes mesh (its
    // corners rounded) never reach. The exact points include it.
    const PhantomSpec cube = phantom_preset("cube", {64, 64, 64});  // side 40
    const double t = 3;
    const Mesh mesh = cube_with_a_corner_cut(cube.centre_or_default(), cube.side / 2, t);
    const auto grid = openvdb::FloatGrid::create(0.f);  // index space = world space; no samples needed
    AccuracyOptions options{20000, exact_distance(cube), phantom_surface_points(cube, 20000)};
    const TrueSurface truth(*grid, 0.5, Inside::above, options);
    EXPECT_EQ(truth.reference_triangles(), 0u);
    const Accuracy accuracy = truth.measure(mesh);
    // Float vertices about 50 voxels from the origin: 4e-6 voxel of rounding.
    EXPECT_NEAR(accuracy.distance.max_b_to_a, t / std::sqrt(3.0), 1e-4);
    EXPECT_NEAR(accuracy.distance.hausdorff, t / std::sqrt(3.0), 1e-4);
    EXPECT_LE(accuracy.distance.max_a_to_b, t / 3 + 1e-4);
    EXPECT_GT(accuracy.distance.max_a_to_b, 0.0);  // the cut, 7.8 of 9,600 voxels^2, holds about 16 of the mesh's samples
}

TEST_F(CompareTest, VolumeToMeshAtFullAdaptivityIsFartherFromTheTrilinearIsosurfaceThanMc) {
    const TrueSurface truth(*grid_, 0.5, Inside::above, {20000, {}});
    const Accuracy mc = truth.measure(mesh_with(*grid_, MeshMethod::mc));
    const Accuracy coarse = truth.measure(mesh_with(*grid_, MeshMethod::openvdb, 1.0));
    // Same bound as against the exact sphere (the trilinear surface is closer still to MC).
    EXPECT_LT(mc.distance.hausdorff, 0.05);
    EXPECT_EQ(mc.unresolved_samples, 0u);
    // Merged quads spanning several voxels cut the sphere's chords: tenths of a voxel.
    EXPECT_GT(coarse.distance.hausdorff, 0.2);
    EXPECT_GT(coarse.distance.mean, mc.distance.mean);
    EXPECT_GT(coarse.normals.mean_deg, mc.normals.mean_deg);
}

TEST_F(CompareTest, CompareMeshersRunsEverySettingInOrder) {
    CompareOptions options;
    options.iso = 0.5;
    options.errors = {0, 0.25};
    options.adaptivities = {0, 1};
    options.budget_rows = false;  // (CompareCliTest checks them)
    options.accuracy = {5000, exact_distance(*sphere_)};
    std::size_t calls = 0;
    options.progress = [&](std::size_t, std::size_t count) {
        ++calls;
        EXPECT_EQ(count, 5u);
    };
    const Comparison result = compare_meshers(*grid_, options);
    ASSERT_EQ(result.meshes.size(), 5u);
    EXPECT_EQ(calls, 6u);  // before each mesh, and once at the end
    EXPECT_EQ(result.meshes[0].method, MeshMethod::dc);
    EXPECT_EQ(result.meshes[1].error, 0.25);
    EXPECT_EQ(result.meshes[2].method, MeshMethod::mc);
    EXPECT_FALSE(result.meshes[2].error.has_value());
    EXPECT_EQ(result.meshes[4].adaptivity, 1.0);
    EXPECT_GT(result.reference_triangles, 0u);
    // DC at error 0 is MC (dual_contouring.h): the same mesh, measured once; every other mesh differs.
    EXPECT_EQ(result.meshes[0].analysis.triangles, result.meshes[2].analysis.triangles);
    EXPECT_EQ(result.meshes[2].same_mesh_as, std::optional<std::size_t>(0));
    EXPECT_EQ(result.meshes[2].accuracy.distance.hausdorff, result.meshes[0].accuracy.distance.hausdorff);
    for (const std::size_t i : {0, 1, 3, 4}) EXPECT_FALSE(result.meshes[i].same_mesh_as.has_value()) << i;
    // The claim checked without compare: both meshed again, vertex for vertex.
    const Mesh dc = mesh_with(*grid_, MeshMethod::dc), mc = mesh_with(*grid_, MeshMethod::mc);
    EXPECT_EQ(dc.vertices, mc.vertices);
    EXPECT_EQ(dc.triangles, mc.triangles);
    for (const auto& m : result.meshes) {
        EXPECT_TRUE(m.analysis.closed) << method_name(m.method);
        EXPECT_GT(m.analysis.triangles, 0u);
        EXPECT_GE(m.seconds, 0.0);
        EXPECT_EQ(m.mesher.method, m.method);
        EXPECT_FALSE(m.mesher.phases.empty());
    }
}

TEST_F(CompareTest, BudgetRowsTheDcRowsMeetAreTheBudgetsMeshWithoutMeshingAgain) {
    CompareOptions options;
    options.iso = 0.5;
    options.errors = {0, 0.1, 0.25, 0.5, 1, 2};
    options.adaptivities = {0, 1};
    options.accuracy = {2000, exact_distance(*sphere_)};
    const Comparison result = compare_meshers(*grid_, options);
    ASSERT_EQ(result.meshes.size(), 11u);  // 6 DC, MC, 2 volumeToMesh, 2 budgets
    bool from_rows = false;
    for (const std::size_t i : {9u, 10u}) {
        const MeshComparison& budget = result.meshes[i];
        ASSERT_TRUE(budget.budget.has_value());
        // Judged by mesh_to_budget() itself, run here.
        MeshOptions mesh_options;
        mesh_options.iso = 0.5;
        const Mesh direct = mesh_to_budget(*grid_, mesh_options, *budget.budget).mesh;
        EXPECT_EQ(budget.analysis.triangles, direct.triangles.size()) << i;
        if (!budget.same_mesh_as) continue;
        const MeshComparison& row = result.meshes[*budget.same_mesh_as];
        if (row.method != MeshMethod::dc || !row.error) continue;
        from_rows = true;
        mesh_options.error = *row.error;
        const Mesh kept = mesh_grid(*grid_, mesh_options).mesh;
        EXPECT_EQ(kept.vertices, direct.vertices) << i;
        EXPECT_EQ(kept.triangles, direct.triangles) << i;
        EXPECT_GE(budget.seconds, row.seconds) << i;  // the kept mesh's time and those of the meshes tried before it
        EXPECT_EQ(budget.accuracy.distance.hausdorff, row.accuracy.distance.hausdorff) << i;
    }
    EXPECT_TRUE(from_rows);  // the budget at volumeToMesh a = 0's count is met by the error-0 row
}

}  // namespace
}  // namespace vdbmesh
