// phantom_surface_points(): the reference points `compare --phantom` measures from lie on the
// exact surface, include the corners and the edges, and are spread uniformly by area (each
// share checked against an area worked out by hand, within five standard deviations of a
// binomial count).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "vdbmesh/phantom.h"

namespace vdbmesh {
namespace phantom_surface_test {  // (named: the folder's tests are one unity translation unit)

using Point = std::array<double, 3>;
constexpr double kPi = 3.14159265358979323846;

/// Points in the shape's centred frame (the presets are unrotated but for rotated-cube).
std::vector<Point> centred(const PhantomSpec& spec, const std::vector<Point>& points) {
    const Point c = spec.centre_or_default();
    std::vector<Point> out;
    for (const Point& p : points) out.push_back({p[0] - c[0], p[1] - c[1], p[2] - c[2]});
    return out;
}

double norm(const Point& p) { return std::hypot(p[0], p[1], p[2]); }

/// Expects @a count of @a n draws to match the probability @a share within 5 binomial sigmas.
void expect_share(std::size_t count, std::size_t n, double share, const char* what) {
    const double sigma = std::sqrt(double(n) * share * (1 - share));
    EXPECT_NEAR(double(count), double(n) * share, 5 * sigma + 1) << what;
}

std::size_t count_if(const std::vector<Point>& points, const std::function<bool(const Point&)>& test) {
    return std::size_t(std::count_if(points.begin(), points.end(), test));
}

TEST(PhantomSurfaceTest, CubePointsAreOnItsFacesWithEveryCornerAndTheEdges) {
    const PhantomSpec spec = phantom_preset("cube", {64, 64, 64});  // side 40
    const double h = 20;
    const std::size_t n = 20000;
    const auto points = centred(spec, phantom_surface_points(spec, n));
    ASSERT_EQ(points.size(), n);
    for (const Point& p : points) ASSERT_NEAR(std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])}), h, 1e-9);
    const auto on_boundary = [&](const Point& p, int axis) { return std::abs(std::abs(p[axis]) - h) < 1e-9; };
    const auto boundaries = [&](const Point& p) { return on_boundary(p, 0) + on_boundary(p, 1) + on_boundary(p, 2); };
    EXPECT_EQ(count_if(points, [&](const Point& p) { return boundaries(p) == 3; }), 8u);  // the corners
    // A tenth along the twelve edges, evenly: 166 or 167 to an edge, 0.24 voxel apart.
    const std::size_t edge_points = count_if(points, [&](const Point& p) { return boundaries(p) == 2; });
    EXPECT_NEAR(double(edge_points), n / 10.0, 12);
    const std::size_t face_points = n - 8 - edge_points;
    for (int axis = 0; axis < 3; ++axis)
        expect_share(count_if(points, [&](const Point& p) { return boundaries(p) == 1 && p[axis] > h - 1e-9; }), face_points, 1 / 6.0, "face");
    EXPECT_EQ(phantom_surface_points(spec, n), phantom_surface_points(spec, n));  // the same points each call
}

TEST(PhantomSurfaceTest, RotatedCubeKeepsItsEightCorners) {
    const PhantomSpec spec = phantom_preset("rotated-cube", {128, 128, 128});  // side 64
    const auto points = centred(spec, phantom_surface_points(spec, 5000));
    // The corners are the only points of a cube at half its diagonal from the centre.
    EXPECT_EQ(count_if(points, [](const Point& p) { return std::abs(norm(p) - 32 * std::sqrt(3.0)) < 1e-9; }), 8u);
    for (const Point& p : phantom_surface_points(spec, 5000)) ASSERT_LT(std::abs(phantom_signed_distance(spec, p[0], p[1], p[2])), 1e-9);
}

TEST(PhantomSurfaceTest, CurvedShapesAreCoveredUniformlyByArea) {
    const std::size_t n = 20000;
    {  // A sphere's zone above half the radius is a quarter of it (Archimedes).
        const PhantomSpec spec = phantom_preset("sphere", {64, 64, 64});
        const auto points = centred(spec, phantom_surface_points(spec, n));
        for (const Point& p : points) ASSERT_NEAR(norm(p), spec.radius, 1e-9);
        expect_share(count_if(points, [&](const Point& p) { return p[2] > spec.radius / 2; }), n, 0.25, "sphere zone");
    }
    {  // A torus's outer half (cos v > 0) has (pi R + 2 r) / (2 pi R) of its area.
        const PhantomSpec spec = phantom_preset("torus", {64, 64, 64});
        const double big = spec.radius, small = spec.tube_radius;
        const auto points = centred(spec, phantom_surface_points(spec, n));
        for (const Point& p : points) ASSERT_NEAR(std::hypot(std::hypot(p[0], p[1]) - big, p[2]), small, 1e-9);
        expect_share(count_if(points, [&](const Point& p) { return std::hypot(p[0], p[1]) > big; }), n,
                     (kPi * big + 2 * small) / (2 * kPi * big), "torus outer half");
    }
    {  // The cylinder's caps are r / (r + height) of its area; its rims have a tenth of the points.
        const PhantomSpec spec = phantom_preset("cylinder", {64, 64, 64});
        const double r = spec.radius, hh = spec.height / 2;
        const auto points = centred(spec, phantom_surface_points(spec, n));
        const auto on_rim = [&](const Point& p) { return std::abs(std::hypot(p[0], p[1]) - r) < 1e-9 && std::abs(std::abs(p[2]) - hh) < 1e-9; };
        const std::size_t rim = count_if(points, on_rim);
        EXPECT_NEAR(double(rim), n / 10.0, 2);
        expect_share(count_if(points, [&](const Point& p) { return !on_rim(p) && std::abs(std::abs(p[2]) - hh) < 1e-9; }), n - rim,
                     r / (r + 2 * hh), "cylinder caps");
    }
    {  // Cube minus sphere: the sphere's part inside the cube, 4 pi rs^2 less six caps of height rs - h.
        const PhantomSpec spec = phantom_preset("cube-minus-sphere", {64, 64, 64});  // side 40, hole 25
        const double h = spec.side / 2, rs = spec.hole_radius;
        const auto points = centred(spec, phantom_surface_points(spec, n));
        const auto on_sphere = [&](const Point& p) { return std::abs(norm(p) - rs) < 1e-9; };
        const auto on_cube = [&](const Point& p) { return std::abs(std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])}) - h) < 1e-9; };
        for (const Point& p : points) ASSERT_TRUE(on_sphere(p) || on_cube(p));
        const std::size_t edges = count_if(points, [&](const Point& p) { return on_sphere(p) && on_cube(p); }) +
                                  count_if(points, [&](const Point& p) {
                                      int boundaries = 0;
                                      for (int a = 0; a < 3; ++a) boundaries += std::abs(std::abs(p[a]) - h) < 1e-9;
                                      return boundaries >= 2;
                                  });
        EXPECT_NEAR(double(edges), n / 10.0 + 8, 12);  // the twelve cube edges, six circles, eight corners
        const double sphere_part = 4 * kPi * rs * rs - 6 * 2 * kPi * rs * (rs - h);
        const double faces = 6 * (4 * h * h - kPi * (rs * rs - h * h));
        expect_share(count_if(points, [&](const Point& p) { return on_sphere(p) && !on_cube(p); }), n - edges,
                     sphere_part / (sphere_part + faces), "sphere part");
    }
}

}  // namespace phantom_surface_test
}  // namespace vdbmesh
