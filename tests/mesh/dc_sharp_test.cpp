// `--sharp` (MeshOptions::sharp, issue 29 item 3) against the exact surfaces of the phantoms of
// include/vdbmesh/phantom.h, converted like scans: the guarantees judged by CGAL, the accuracy
// by this file's own points on the exact surfaces (faces, edges and corners included: points
// projected from a mesh onto a cube's faces would miss its corners, where a rounded mesh is
// farthest), measured with mesh_distance() (two-sided Hausdorff, voxels).

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <openvdb/openvdb.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "cgal_judge.h"
#include "cli.h"
#include "mesh/dc_feature_window.h"
#include "mesh/sample_classifier.h"
#include "mesh_checks.h"
#include "phantom_grid.h"
#include "shared_scan.h"
#include "test_data.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/phantom.h"

namespace vdbmesh {
namespace {

using Points = std::vector<std::array<double, 3>>;
using Vec3 = openvdb::Vec3d;
const double kPi = std::acos(-1.0);

PhantomSpec preset(const char* name) { return phantom_preset(name, {128, 128, 128}); }

/// world = Rz * Ry * Rx * shape about the centre, as PhantomSpec::rotation_degrees (built from
/// OpenVDB's axis rotations, not the phantom's own code; OpenVDB's are for row vectors, hence
/// the transposes).
Vec3 placed(const PhantomSpec& spec, const Vec3& local) {
    const auto& d = spec.rotation_degrees;
    const auto about = [](openvdb::math::Axis axis, double degrees) {
        return openvdb::math::rotation<openvdb::Mat3d>(axis, degrees * kPi / 180).transpose();
    };
    const openvdb::Mat3d r = about(openvdb::math::Z_AXIS, d[2]) * about(openvdb::math::Y_AXIS, d[1]) * about(openvdb::math::X_AXIS, d[0]);
    const auto c = spec.centre_or_default();
    return r * local + Vec3(c[0], c[1], c[2]);
}

/// @a world in the cube's own axes about its centre (the inverse rotation: the offset's
/// components along the images of the axes).
Vec3 in_cube_axes(const PhantomSpec& spec, const Vec3& world) {
    const Vec3 centre = placed(spec, Vec3(0, 0, 0));
    const Vec3 d = world - centre;
    return {d.dot(placed(spec, Vec3(1, 0, 0)) - centre), d.dot(placed(spec, Vec3(0, 1, 0)) - centre),
            d.dot(placed(spec, Vec3(0, 0, 1)) - centre)};
}

/// Points on the six faces of a cube of edge @a side about the origin (shape coordinates), a
/// grid of @a n + 1 by n + 1 on each, so its edges and corners are among them; @a keep decides.
template <class Keep>
void cube_face_points(double side, int n, Keep&& keep, std::vector<Vec3>& out) {
    for (int axis = 0; axis < 3; ++axis) {
        for (double sign : {-1.0, 1.0}) {
            for (int i = 0; i <= n; ++i) {
                for (int j = 0; j <= n; ++j) {
                    Vec3 p;
                    p[axis] = sign * side / 2;
                    p[(axis + 1) % 3] = side * (double(i) / n - 0.5);
                    p[(axis + 2) % 3] = side * (double(j) / n - 0.5);
                    if (keep(p)) out.push_back(p);
                }
            }
        }
    }
}

/// Points on the exact surface of @a spec, about half a voxel apart, every edge and corner
/// included: cubes, cube minus sphere (the ball's part inside the cube and the six circles where
/// it meets the faces) and the cylinder (side, caps and both rims).
Points exact_surface_points(const PhantomSpec& spec) {
    std::vector<Vec3> local;
    const auto all = [](const Vec3&) { return true; };
    switch (spec.shape) {
        case PhantomShape::cube: cube_face_points(spec.side, int(2 * spec.side), all, local); break;
        case PhantomShape::cube_minus_sphere: {
            const double r = spec.hole_radius, half = spec.side / 2;
            cube_face_points(spec.side, int(2 * spec.side), [&](const Vec3& p) { return p.length() >= r; }, local);
            const int n = int(4 * kPi * r * r);  // about one point per quarter voxel^2
            const double golden = kPi * (3.0 - std::sqrt(5.0));
            for (int i = 0; i < n; ++i) {
                const double z = 1.0 - 2.0 * (i + 0.5) / n, s = std::sqrt(1.0 - z * z);
                const Vec3 p = r * Vec3(s * std::cos(golden * i), s * std::sin(golden * i), z);
                if (std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])}) <= half) local.push_back(p);
            }
            const double rim = std::sqrt(r * r - half * half);  // the circles on the faces
            for (int axis = 0; axis < 3; ++axis) {
                for (double sign : {-1.0, 1.0}) {
                    for (int k = 0; k < int(4 * kPi * rim); ++k) {
                        const double t = 2 * kPi * k / int(4 * kPi * rim);
                        Vec3 p;
                        p[axis] = sign * half;
                        p[(axis + 1) % 3] = rim * std::cos(t);
                        p[(axis + 2) % 3] = rim * std::sin(t);
                        local.push_back(p);
                    }
                }
            }
            break;
        }
        case PhantomShape::cylinder: {
            const double r = spec.radius, h = spec.height / 2;
            const int around = int(4 * kPi * r);
            for (int k = 0; k < around; ++k) {
                const double t = 2 * kPi * k / around;
                for (int j = 0; j <= int(4 * h); ++j) local.emplace_back(r * std::cos(t), r * std::sin(t), -h + 2 * h * j / int(4 * h));
            }
            for (int i = -int(2 * r); i <= int(2 * r); ++i) {
                for (int j = -int(2 * r); j <= int(2 * r); ++j) {
                    const double x = i / 2.0, y = j / 2.0;
                    if (x * x + y * y > r * r) continue;
                    local.emplace_back(x, y, -h);
                    local.emplace_back(x, y, h);
                }
            }
            break;
        }
        default: ADD_FAILURE() << "no exact points for this shape";
    }
    Points points;
    for (const Vec3& p : local) {
        const Vec3 w = placed(spec, p);
        EXPECT_NEAR(phantom_signed_distance(spec, w[0], w[1], w[2]), 0.0, 1e-9);  // on the exact surface
        points.push_back({w[0], w[1], w[2]});
    }
    return points;
}

MeshOptions dc_at(double error, bool sharp) {
    MeshOptions options;
    options.iso = 0.5;
    options.error = error;
    options.sharp = sharp;
    return options;
}

struct SharpRun {
    Mesh mesh;
    DistanceReport distance;
};

SharpRun mesh_and_measure(const openvdb::FloatGrid& grid, const PhantomSpec& spec, const Points& exact, const MeshOptions& options) {
    SharpRun run;
    run.mesh = mesh_grid(grid, options).mesh;
    run.distance = mesh_distance(
        run.mesh, [&](double x, double y, double z) { return phantom_signed_distance(spec, x, y, z); }, 200000, exact);
    return run;
}

void expect_clean(const Mesh& mesh) {
    const test::CgalVerdict verdict = test::judge_with_cgal(mesh);
    EXPECT_TRUE(verdict.clean()) << verdict.describe();
}

/// `--sharp --error 0.1` on a phantom with sharp edges: clean, and no farther from the exact
/// surface than DC without it. Returns the runs (error 0, error 0.1, --sharp) for the figures.
std::array<SharpRun, 3> expect_sharp_no_worse(const char* name) {
    const PhantomSpec spec = preset(name);
    const auto grid = test::phantom_scan_grid(spec);
    const Points exact = exact_surface_points(spec);
    std::array<SharpRun, 3> runs = {mesh_and_measure(*grid, spec, exact, dc_at(0.0, false)),
                                    mesh_and_measure(*grid, spec, exact, dc_at(0.1, false)),
                                    mesh_and_measure(*grid, spec, exact, dc_at(0.1, true))};
    std::printf("[ figures  ] %s: error 0: %zu triangles, Hausdorff %.3f; error 0.1: %zu, %.3f; --sharp: %zu, %.3f\n", name,
                runs[0].mesh.triangles.size(), runs[0].distance.hausdorff, runs[1].mesh.triangles.size(), runs[1].distance.hausdorff,
                runs[2].mesh.triangles.size(), runs[2].distance.hausdorff);
    EXPECT_LE(runs[2].distance.hausdorff, runs[1].distance.hausdorff);
    EXPECT_LE(runs[2].mesh.triangles.size(), runs[1].mesh.triangles.size());
    expect_clean(runs[2].mesh);
    return runs;
}

/// The share of the points of @a exact on the edges of the cube of @a spec (its corners
/// excepted) farther than @a limit voxels from @a mesh.
double edge_points_beyond(const Mesh& mesh, const PhantomSpec& spec, const Points& exact, double limit) {
    std::vector<std::uint32_t> all(mesh.triangles.size());
    std::iota(all.begin(), all.end(), 0u);
    const detail::TriangleBvh bvh(mesh, std::move(all));
    int on_edges = 0, beyond = 0;
    for (const auto& p : exact) {
        const Vec3 local = in_cube_axes(spec, Vec3(p[0], p[1], p[2]));
        int faces = 0;
        for (int a = 0; a < 3; ++a) faces += std::abs(std::abs(local[a]) - spec.side / 2) < 1e-6;
        if (faces != 2) continue;
        ++on_edges;
        beyond += bvh.closest_point(p, limit * limit).distance_squared >= limit * limit;
    }
    EXPECT_GT(on_edges, 0);
    return double(beyond) / on_edges;
}

// Issue 29 asks `--sharp --error 0.1` within 0.2 voxel of the exact cube with 10x fewer
// triangles than at error 0 (docs/dmc.md, "Sharp features"): met on the axis-aligned cube, NOT
// on the tilted one. A feature cell's point is where the faces found in a window 3 voxels wider
// than the cell meet (dc_feature_window.cpp); along the tilted cube's edges many cells of 2
// voxels fail the topology tests (the edge pokes through the middle sample of a cell edge), and
// their simple unit cells take the feature point instead (session 24). Where the edge only clips
// a cell whose samples are all outside, or a corner lies in one (0.64-0.71 voxel beyond the
// trilinear isosurface), no cell round it can hold the feature, and the mesh dips. Measured (this
// test, 128^3): axis-aligned error 0 76,796 triangles, Hausdorff 0.577; error 0.1 8,348, 0.577;
// --sharp 3,228, 0.000. Tilted: 72,188, 0.758; 14,428, 0.758; --sharp 11,110, 0.739, with 5.4%
// of the points on its edges beyond 0.2 voxel (24.6% before unit cells took feature points).
// What is held here: clean, no farther than without --sharp, the axis-aligned cube within the
// issue's 0.2 voxel and 10x lighter, the tilted cube's edges within 0.2 voxel but for 6% of
// their points (the measured 5.4% and some room).
TEST(DcSharpTest, CubesAreCleanAndCloserToTheExactCubeThanWithoutSharp) {
    const auto aligned = expect_sharp_no_worse("cube");
    EXPECT_LE(aligned[2].distance.hausdorff, 0.2);  // the bar
    EXPECT_LE(10 * aligned[2].mesh.triangles.size(), aligned[0].mesh.triangles.size());
    const auto tilted = expect_sharp_no_worse("rotated-cube");
    const PhantomSpec spec = preset("rotated-cube");
    const double share = edge_points_beyond(tilted[2].mesh, spec, exact_surface_points(spec), 0.2);
    std::printf("[ figures  ] rotated-cube --sharp: %.1f%% of the edges' points beyond 0.2 voxel\n", 100 * share);
    EXPECT_LE(share, 0.06);
}

// Measured (128^3): cube minus sphere error 0 80,608 triangles, Hausdorff 0.830; error 0.1
// 37,010, 0.871; --sharp 29,082, 0.871. Cylinder: 96,892, 0.476; 10,052, 0.476; 6,770, 0.436.
TEST(DcSharpTest, CubeMinusSphereAndCylinderAreCleanAndNoFartherFromTheirExactSurfaces) {
    expect_sharp_no_worse("cube-minus-sphere");
    expect_sharp_no_worse("cylinder");
}

// Away from features the mesh is the one without --sharp: on smooth phantoms no cell holds an
// edge or a corner, so the whole mesh is the same, vertex for vertex.
TEST(DcSharpTest, SmoothSurfacesGiveTheSameMesh) {
    for (const char* name : {"sphere", "torus"}) {
        const auto grid = test::phantom_scan_grid(preset(name));
        for (double error : {0.1, 0.25, 1.0}) {
            const Mesh plain = mesh_grid(*grid, dc_at(error, false)).mesh;
            const Mesh sharp = mesh_grid(*grid, dc_at(error, true)).mesh;
            EXPECT_EQ(plain.vertices, sharp.vertices) << name << " at " << error;
            EXPECT_EQ(plain.triangles, sharp.triangles) << name << " at " << error;
        }
    }
}

/// window_feature_point() for the cell of @a size holding @a point of @a grid (its minimum
/// corner a multiple of @a size), from the estimate @a estimate.
std::optional<std::array<double, 3>> feature_point_near(const openvdb::FloatGrid& grid, const Vec3& point, int size, const Vec3& estimate) {
    const detail::SampleClassifier classifier(grid, dc_at(0.1, true));
    auto accessor = grid.getConstAccessor();
    openvdb::Coord min;
    for (int a = 0; a < 3; ++a) min[a] = int(std::floor(point[a] / size)) * size;
    return detail::window_feature_point({&accessor, &classifier}, 0.5, min, size, {estimate[0], estimate[1], estimate[2]});
}

// The window's faces meet at the exact corner (the phantoms' own geometry, placed() above): on
// the axis-aligned cube (cells of 2 and 8) and on the tilted one (cells of 8: a cell of 2 at a
// tilted corner may see too few exact crossings of a face within its window), from an estimate
// 0.4 voxel inside along the diagonal (where the cell's own QEF puts it, docs/dmc.md). 0.02
// voxel: the faces' crossings are exact to the floats' 1e-6, but a face's plane is averaged over
// crossings whose normals agree within 1.8 degrees. On the sphere no two faces pin down a feature.
TEST(DcSharpTest, TheWindowsFacesMeetAtTheExactCorner) {
    for (const char* name : {"cube", "rotated-cube"}) {
        const PhantomSpec spec = preset(name);
        const auto grid = test::phantom_scan_grid(spec);
        const Vec3 centre = placed(spec, Vec3(0, 0, 0));
        for (const Vec3& local : {Vec3(-1, -1, -1), Vec3(1, -1, 1), Vec3(1, 1, 1)}) {
            const Vec3 corner = placed(spec, local * (spec.side / 2));
            const Vec3 inward = (centre - corner).unitSafe();
            for (int size : std::string(name) == "cube" ? std::vector<int>{2, 8} : std::vector<int>{8}) {
                const auto point = feature_point_near(*grid, corner, size, corner + 0.4 * inward);
                ASSERT_TRUE(point) << name << " corner " << corner << ", cell of " << size;
                EXPECT_LT((Vec3((*point)[0], (*point)[1], (*point)[2]) - corner).length(), 0.02) << name << " corner " << corner;
            }
        }
    }
    const PhantomSpec sphere = preset("sphere");
    const auto grid = test::phantom_scan_grid(sphere);
    const Vec3 on_surface = placed(sphere, Vec3(1, 2, 2) * (sphere.radius / 3));
    EXPECT_FALSE(feature_point_near(*grid, on_surface, 4, on_surface));
}

// The same bytes for any thread count, as without --sharp.
TEST(DcSharpTest, OneAndTwoThreadsGiveTheSameMesh) {
    const auto grid = test::phantom_scan_grid(preset("rotated-cube"));
    Mesh meshes[2];
    for (int threads : {1, 2}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        meshes[threads - 1] = mesh_grid(*grid, dc_at(0.1, true)).mesh;
    }
    EXPECT_EQ(meshes[0].vertices, meshes[1].vertices);
    EXPECT_EQ(meshes[0].triangles, meshes[1].triangles);
}

// The feature point reads samples up to 4 voxels beyond its cell (dc_feature_window.h): by
// bricks of one and two nodes, 1 and 2 threads, the same bytes as the whole grid, on the tilted
// cube placed where eight nodes meet (its edges and corners cross the node borders).
TEST(DcSharpTest, BricksGiveTheWholeGridsMesh) {
    PhantomSpec spec = phantom_preset("rotated-cube", {168, 168, 168});
    spec.centre = std::array<double, 3>{128.3, 127.6, 128.45};
    const auto grid = test::phantom_scan_grid(spec);
    const MeshOptions options = dc_at(0.1, true);
    Mesh whole;
    tbb::task_arena(2).execute([&] { whole = mesh_grid(*grid, options).mesh; });
    const std::unique_ptr<GridRegionSource> source = grid_regions_in_memory(grid);
    for (const auto& [nodes_x, threads] : std::vector<std::pair<int, int>>{{1, 1}, {1, 2}, {2, 2}}) {
        BrickShape shape;
        shape.nodes_x = nodes_x;
        shape.nodes_y = 1;
        Mesh bricked;
        tbb::task_arena(threads).execute([&] { bricked = mesh_bricks(*source, options, BrickOptions{shape}).mesh; });
        EXPECT_EQ(bricked.vertices, whole.vertices) << nodes_x << " node(s) a brick, " << threads << " thread(s)";
        EXPECT_EQ(bricked.triangles, whole.triangles) << nodes_x << " node(s) a brick, " << threads << " thread(s)";
    }
}

/// The triangles of @a mesh whose corners all lie more than @a away voxels from every edge of
/// the cube of @a spec, as corner positions (orientation kept, starting at the least corner).
std::set<std::array<std::array<float, 3>, 3>> triangles_away_from_edges(const Mesh& mesh, const PhantomSpec& spec, double away) {
    const auto far_from_edges = [&](const std::array<float, 3>& v) {
        const Vec3 d = in_cube_axes(spec, Vec3(v[0], v[1], v[2]));
        std::array<double, 3> gaps = {spec.side / 2 - std::abs(d[0]), spec.side / 2 - std::abs(d[1]), spec.side / 2 - std::abs(d[2])};
        std::sort(gaps.begin(), gaps.end());
        return gaps[1] > away;  // a point near an edge is near two faces
    };
    std::set<std::array<std::array<float, 3>, 3>> kept;
    for (const auto& t : mesh.triangles) {
        std::array<std::array<float, 3>, 3> corners;
        bool far = true;
        for (int k = 0; k < 3; ++k) {
            const std::array<float, 3>& v = mesh.vertices[t[k]];
            far &= far_from_edges(v);
            corners[k] = {v[0], v[1], v[2]};
        }
        if (!far) continue;
        std::rotate(corners.begin(), std::min_element(corners.begin(), corners.end()), corners.end());
        kept.insert(corners);
    }
    return kept;
}

// On the cubes, the triangles farther than two blocks (16 voxels) from the edges are the same.
// Nearer, the merge across blocks may differ too: an edge's block is now one feature cell, a
// leaf the coarse merge can take (measured: within 8 and 12 voxels the tilted cube's triangles
// differ, 390 against 384 and 119 against 118).
TEST(DcSharpTest, CubesAwayFromTheirEdgesGiveTheSameTriangles) {
    constexpr double kAway = 16.0;
    for (const char* name : {"cube", "rotated-cube"}) {
        const PhantomSpec spec = preset(name);
        const auto grid = test::phantom_scan_grid(spec);
        const Mesh plain = mesh_grid(*grid, dc_at(0.1, false)).mesh;
        const Mesh sharp = mesh_grid(*grid, dc_at(0.1, true)).mesh;
        const auto a = triangles_away_from_edges(plain, spec, kAway), b = triangles_away_from_edges(sharp, spec, kAway);
        EXPECT_GT(a.size(), 0u);
        EXPECT_EQ(a, b) << name << ": " << a.size() << " and " << b.size() << " triangles away from the edges";
    }
}

// On real scans `--sharp` is judged by the guarantees alone (issue 29): CGAL on the walnut at
// 0.25 and 1 (5 s; the CThead as well took 11 s), every staged scan with VDBMESH_FULL=1.
TEST(DcSharpTest, RealScansAreCleanWithSharp) {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
    std::vector<test::SharedScan> scans;
    if (std::getenv("VDBMESH_FULL")) scans = test::shared_scans();
    else scans = {test::shared_scan("WalnutOpenQVis")};
    for (const test::SharedScan& scan : scans) {
        openvdb::FloatGrid::Ptr grid;
        ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan, grid));
        if (!grid) return;  // skipped: the shared data is missing
        for (double error : {0.25, 1.0}) {
            MeshOptions options = dc_at(error, true);
            options.iso = scan.iso;
            const Mesh mesh = mesh_grid(*grid, options).mesh;
            const test::CgalVerdict verdict = test::judge_with_cgal(mesh);
            EXPECT_TRUE(verdict.clean()) << scan.name << " --sharp --error " << error << ": " << verdict.describe();
            std::printf("[ figures  ] %s --sharp --error %g: %zu triangles, clean %d\n", scan.name.c_str(), error, mesh.triangles.size(),
                        int(verdict.clean()));
        }
    }
}

// `vdbmesh mesh --sharp`: the library's mesh, "sharp" in --json; refused (usage, nothing
// written) where it would change nothing or could not be kept.
TEST(DcSharpTest, TheCommandLineMeshesWithSharpAndRefusesWhereItDoesNotApply) {
    test::ScratchDir scratch;
    const auto grid = test::make_ball(6, {0.5, 0.25, 0.1});
    grid->insertMeta(kMetaIsovalue, openvdb::DoubleMetadata(0.0));
    const auto input = scratch / "ball.vdb", output = scratch / "ball.ply";
    write_vdb(*grid, input);
    testing::internal::CaptureStdout();
    const int status = cli::run({"mesh", input.string(), "--error", "0.25", "--sharp", "-o", output.string(), "--json"});
    const std::string json = testing::internal::GetCapturedStdout();
    ASSERT_EQ(status, cli::kSuccess);
    EXPECT_EQ(nlohmann::json::parse(json)["sharp"], true);
    MeshOptions options = dc_at(0.25, true);
    options.iso = 0.0;
    EXPECT_EQ(read_mesh(output).triangles.size(), mesh_grid(*grid, options).mesh.triangles.size());
    const std::vector<std::vector<std::string>> refused = {
        {"--sharp", "--method", "mc"}, {"--sharp"}, {"--sharp", "--error", "0"}, {"--sharp", "--triangles", "100"}};
    for (const auto& flags : refused) {
        const auto none = scratch / "refused.ply";
        std::vector<std::string> args = {"mesh", input.string(), "-o", none.string()};
        args.insert(args.end(), flags.begin(), flags.end());
        testing::internal::CaptureStderr();
        EXPECT_EQ(cli::run(args), cli::kUsageError) << args.back();
        EXPECT_NE(testing::internal::GetCapturedStderr().find("--sharp: only"), std::string::npos);
        EXPECT_FALSE(std::filesystem::exists(none));
    }
}

}  // namespace
}  // namespace vdbmesh
