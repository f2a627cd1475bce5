// Accuracy of intersection-free DC (MeshMethod::dc) against exact surfaces: phantoms of 128^3
// samples whose density is the coursework's ramp s(d, w) = (w - d) / (2w) of the exact signed
// distance d (blur w = 5 voxels, surface at s = 0.5), from include/vdbmesh/phantom.h.

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>

#include "cgal_judge.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/phantom.h"

namespace vdbmesh {
namespace {

constexpr int kDim = 128;
const double kPi = std::acos(-1.0);

using Vec3 = openvdb::Vec3d;
using SignedDistance = std::function<double(const Vec3&)>;

PhantomSpec phantom_spec(PhantomShape shape) {
    PhantomSpec spec;
    spec.shape = shape;
    spec.dims = {kDim, kDim, kDim};
    return spec;  // blur 5 voxels, centre (63.5, 63.5, 63.5)
}

SignedDistance signed_distance(const PhantomSpec& spec) {
    return [spec](const Vec3& p) { return phantom_signed_distance(spec, p.x(), p.y(), p.z()); };
}

/// The grid of the phantom: 8^3 blocks within the ramp of the surface are leaves with every
/// sample, blocks entirely inside are tiles of 1, the rest background 0.
openvdb::FloatGrid::Ptr phantom_grid(const PhantomSpec& spec) {
    auto grid = openvdb::FloatGrid::create(0.0f);
    const double half_diagonal = 4.5 * std::sqrt(3.0);  // block of 8 plus its ring, from its centre
    for (int x0 = 0; x0 < kDim; x0 += 8) {
        for (int y0 = 0; y0 < kDim; y0 += 8) {
            for (int z0 = 0; z0 < kDim; z0 += 8) {
                const double d = phantom_signed_distance(spec, x0 + 3.5, y0 + 3.5, z0 + 3.5);
                if (d < -spec.blur - half_diagonal) {
                    grid->tree().addTile(1, openvdb::Coord(x0, y0, z0), 1.0f, false);
                } else if (d < spec.blur + half_diagonal) {
                    for (int x = x0; x < x0 + 8; ++x) {
                        for (int y = y0; y < y0 + 8; ++y) {
                            for (int z = z0; z < z0 + 8; ++z) {
                                grid->tree().setValueOn(openvdb::Coord(x, y, z), float(phantom_density(spec, x, y, z)));
                            }
                        }
                    }
                }
            }
        }
    }
    return grid;
}

const Vec3 kCentre(63.5, 63.5, 63.5);

/// Rotation world = Rz * Ry * Rx * shape (degrees), as PhantomSpec::rotation_degrees: the
/// phantom's surface points are placed with it.
openvdb::Mat3d rotation(double ax, double ay, double az) {
    const double d = kPi / 180.0;
    const double cx = std::cos(ax * d), sx = std::sin(ax * d), cy = std::cos(ay * d), sy = std::sin(ay * d);
    const double cz = std::cos(az * d), sz = std::sin(az * d);
    const openvdb::Mat3d rx(1.0, 0.0, 0.0, 0.0, cx, -sx, 0.0, sx, cx);
    const openvdb::Mat3d ry(cy, 0.0, sy, 0.0, 1.0, 0.0, -sy, 0.0, cy);
    const openvdb::Mat3d rz(cz, -sz, 0.0, sz, cz, 0.0, 0.0, 0.0, 1.0);
    return rz * ry * rx;
}

/// Points on the cube's faces, a grid of spacing 1 voxel on each.
std::vector<std::array<double, 3>> cube_points(double side, const openvdb::Mat3d& rot) {
    std::vector<std::array<double, 3>> points;
    const int n = int(side);
    for (int axis = 0; axis < 3; ++axis) {
        for (double sign : {-1.0, 1.0}) {
            for (int i = 0; i <= n; ++i) {
                for (int j = 0; j <= n; ++j) {
                    Vec3 local;
                    local[axis] = sign * side / 2;
                    local[(axis + 1) % 3] = -side / 2 + side * i / n;
                    local[(axis + 2) % 3] = -side / 2 + side * j / n;
                    const Vec3 p = rot * local + kCentre;
                    points.push_back({p.x(), p.y(), p.z()});
                }
            }
        }
    }
    return points;
}

std::vector<std::array<double, 3>> sphere_points(double radius, int count) {
    std::vector<std::array<double, 3>> points;
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < count; ++i) {
        const double z = 1.0 - 2.0 * (i + 0.5) / count, r = std::sqrt(1.0 - z * z);
        const Vec3 p = kCentre + radius * Vec3(r * std::cos(golden * i), r * std::sin(golden * i), z);
        points.push_back({p.x(), p.y(), p.z()});
    }
    return points;
}

std::vector<std::array<double, 3>> torus_points(double major, double minor) {
    std::vector<std::array<double, 3>> points;
    for (int i = 0; i < 400; ++i) {
        for (int j = 0; j < 100; ++j) {
            const double u = 2 * kPi * i / 400, v = 2 * kPi * j / 100;
            const Vec3 p = kCentre + Vec3((major + minor * std::cos(v)) * std::cos(u), (major + minor * std::cos(v)) * std::sin(u),
                                          minor * std::sin(v));
            points.push_back({p.x(), p.y(), p.z()});
        }
    }
    return points;
}

MeshOptions options_at(double error) {
    MeshOptions options;
    options.method = MeshMethod::dc;
    options.iso = 0.5;
    options.error = error;
    return options;
}

DistanceReport distance(const Mesh& mesh, const SignedDistance& sd, const std::vector<std::array<double, 3>>& points) {
    return mesh_distance(mesh, [&](double x, double y, double z) { return sd(Vec3(x, y, z)); }, 200000, points);
}

void expect_clean(const Mesh& mesh) {
    const test::CgalVerdict verdict = test::judge_with_cgal(mesh);
    EXPECT_TRUE(verdict.clean()) << verdict.describe();
}

// At error 0: two-sided Hausdorff <= 0.3 voxel, area within 2%, volume within 0.4%. Until session
// 22 error 0 was Marching Cubes and the targets were 0.05 voxel and 0.2%; the dual mesh holds its
// vertices 0.15 voxel inside their cells (kUnitCellMargin), off the surface where it cuts a
// cell's corner, which makes the surface a little bumpy: measured sphere 0.237 voxel, area
// +1.40%; torus 0.246, area +1.25%, volume -0.23% (docs/dmc.md, "Error 0").
constexpr double kErrorZeroHausdorff = 0.3, kErrorZeroArea = 0.02, kErrorZeroVolume = 0.004;
TEST(DcAccuracyTest, SphereAtErrorZero) {
    const PhantomSpec spec = phantom_spec(PhantomShape::sphere);
    const double radius = spec.radius;
    const SignedDistance sd = signed_distance(spec);
    const Mesh mesh = mesh_grid(*phantom_grid(spec), options_at(0.0)).mesh;
    const DistanceReport d = distance(mesh, sd, sphere_points(radius, 20000));
    EXPECT_LE(d.hausdorff, kErrorZeroHausdorff);
    const MeshIntegrals integrals = mesh_integrals(mesh);
    EXPECT_NEAR(integrals.area / (4 * kPi * radius * radius), 1.0, kErrorZeroArea);
    EXPECT_NEAR(integrals.volume / (4.0 / 3.0 * kPi * radius * radius * radius), 1.0, kErrorZeroVolume);
    expect_clean(mesh);
}

TEST(DcAccuracyTest, TorusAtErrorZero) {
    const PhantomSpec spec = phantom_spec(PhantomShape::torus);
    const double major = spec.radius, minor = spec.tube_radius;
    const SignedDistance sd = signed_distance(spec);
    const Mesh mesh = mesh_grid(*phantom_grid(spec), options_at(0.0)).mesh;
    const DistanceReport d = distance(mesh, sd, torus_points(major, minor));
    EXPECT_LE(d.hausdorff, kErrorZeroHausdorff);
    const MeshIntegrals integrals = mesh_integrals(mesh);
    EXPECT_NEAR(integrals.area / (4 * kPi * kPi * major * minor), 1.0, kErrorZeroArea);
    EXPECT_NEAR(integrals.volume / (2 * kPi * kPi * major * minor * minor), 1.0, kErrorZeroVolume);
    expect_clean(mesh);
}

PhantomSpec cube_spec(const std::array<double, 3>& degrees) {
    PhantomSpec spec = phantom_spec(PhantomShape::cube);  // side 80
    spec.rotation_degrees = degrees;
    return spec;
}
std::vector<std::array<double, 3>> cube_points(const PhantomSpec& spec) {
    const auto& r = spec.rotation_degrees;
    return cube_points(spec.side, rotation(r[0], r[1], r[2]));
}

struct CubeRun {
    Mesh fine, coarse;
    DistanceReport fine_distance, distance;
};
CubeRun mesh_cube(const std::array<double, 3>& degrees, double error) {
    const PhantomSpec spec = cube_spec(degrees);
    const auto grid = phantom_grid(spec);
    CubeRun run;
    run.fine = mesh_grid(*grid, options_at(0.0)).mesh;
    run.coarse = mesh_grid(*grid, options_at(error)).mesh;
    run.fine_distance = distance(run.fine, signed_distance(spec), cube_points(spec));
    run.distance = distance(run.coarse, signed_distance(spec), cube_points(spec));
    std::printf("cube %g %g %g: error 0: %zu triangles, Hausdorff %.3f; error %g: %zu triangles, Hausdorff %.3f\n",
                degrees[0], degrees[1], degrees[2], run.fine.triangles.size(), run.fine_distance.hausdorff, error,
                run.coarse.triangles.size(), run.distance.hausdorff);
    return run;
}

// Sharp features at error 0.1. DC's vertices stay within the error of the trilinear
// isosurface, which rounds the cube's edges and corners as Marching Cubes does (the exact
// corners lie 0.64-0.71 voxel from it on the tilted cube: RoundedCornerTest), so the bound is
// Marching Cubes' own distance to the exact cube plus twice the error, with at least 5x fewer
// triangles. Measured: axis-aligned 76,796 -> 8,348 triangles, Hausdorff 0.577 (error 0:
// 0.577); tilted 109,468 -> 17,762, 0.691 (error 0: 0.691). The retired DMC's feature QEF
// reached 0.163 on the axis-aligned cube (1,196 triangles) but 0.588 tilted; within 0.2 voxel
// of the corners is what `--sharp` (issue 29, item 3) is for.
void expect_within_marching_cubes_plus_twice_the_error(const CubeRun& run, double error) {
    EXPECT_LE(run.distance.hausdorff, run.fine_distance.hausdorff + 2 * error);
    EXPECT_LE(run.coarse.triangles.size() * 5, run.fine.triangles.size());
    expect_clean(run.coarse);
}

TEST(DcAccuracyTest, AxisAlignedCubeAtErrorPointOneIsCleanAndCoarser) {
    expect_within_marching_cubes_plus_twice_the_error(mesh_cube({0, 0, 0}, 0.1), 0.1);
}

TEST(DcAccuracyTest, TiltedCubeAtErrorPointOneIsCleanAndCoarser) {
    expect_within_marching_cubes_plus_twice_the_error(mesh_cube({17, 31, 7}, 0.1), 0.1);
}

// Smooth shapes merge well: at error 0.25 the mesh stays within twice the tolerance (a vertex
// is within the error of every tangent plane in its cell) with far fewer triangles. Measured:
// 60,284 -> 3,762 triangles, Hausdorff 0.239.
TEST(DcAccuracyTest, SphereAtErrorQuarterIsCleanAccurateAndCoarser) {
    const PhantomSpec spec = phantom_spec(PhantomShape::sphere);
    const double radius = spec.radius;
    const SignedDistance sd = signed_distance(spec);
    const auto grid = phantom_grid(spec);
    const Mesh fine = mesh_grid(*grid, options_at(0.0)).mesh;
    const Mesh coarse = mesh_grid(*grid, options_at(0.25)).mesh;
    const DistanceReport d = distance(coarse, sd, sphere_points(radius, 20000));
    std::printf("sphere: error 0: %zu triangles; error 0.25: %zu triangles, Hausdorff %.3f\n", fine.triangles.size(),
                coarse.triangles.size(), d.hausdorff);
    EXPECT_LE(d.hausdorff, 0.5);
    EXPECT_LE(coarse.triangles.size() * 3, fine.triangles.size());
    expect_clean(coarse);
}

/// Deterministic noise in [-amplitude, amplitude] per sample (a hash of its coordinates).
double sample_noise(const openvdb::Coord& c, double amplitude) {
    std::uint32_t h = std::uint32_t(c.x()) * 73856093u ^ std::uint32_t(c.y()) * 19349663u ^ std::uint32_t(c.z()) * 83492791u;
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return amplitude * (2.0 * (h & 0xffffu) / 65535.0 - 1.0);
}

// Scans are noisy: the sample planes then disagree slightly everywhere. Noise of +-0.2 voxel
// (0.02 of the ramp's 0.1 per voxel, RMS 0.12 voxel, below the tolerance) must still let cells
// merge. DC keeps 56% of the error-0 triangles (61,876 -> 34,348, Hausdorff 0.406); the retired
// DMC kept 9% (its smooth merge test accepted cells DC's topology and accuracy tests refuse).
TEST(DcAccuracyTest, NoisySphereAtErrorQuarterIsCleanAndCoarser) {
    const PhantomSpec spec = phantom_spec(PhantomShape::sphere);
    const auto grid = phantom_grid(spec);
    for (auto leaf = grid->tree().beginLeaf(); leaf; ++leaf) {
        for (auto voxel = leaf->beginValueOn(); voxel; ++voxel) voxel.setValue(float(*voxel + sample_noise(voxel.getCoord(), 0.02)));
    }
    const Mesh fine = mesh_grid(*grid, options_at(0.0)).mesh;
    const Mesh coarse = mesh_grid(*grid, options_at(0.25)).mesh;
    const DistanceReport d = distance(coarse, signed_distance(spec), sphere_points(spec.radius, 20000));
    std::printf("noisy sphere: error 0: %zu triangles; error 0.25: %zu triangles, Hausdorff %.3f\n", fine.triangles.size(),
                coarse.triangles.size(), d.hausdorff);
    // Twice the tolerance plus the noise's shift of the isosurface (0.2 voxel).
    EXPECT_LE(d.hausdorff, 0.7);
    EXPECT_LE(double(coarse.triangles.size()), 0.6 * double(fine.triangles.size()));
    expect_clean(coarse);
}

}  // namespace
}  // namespace vdbmesh
