// Phantoms (include/vdbmesh/phantom.h): the blur function of the coursework, the exactness
// of the signed distances, the analytic areas and volumes against brute-force estimates,
// and deterministic noise. The writers are tested in write_volume_test.cpp.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <random>
#include <vector>

#include "vdbmesh/error.h"
#include "vdbmesh/phantom.h"

namespace vdbmesh {
namespace {

using Point = std::array<double, 3>;

/// Every preset, at a volume size small enough for brute-force checks.
std::vector<PhantomSpec> small_presets(std::int64_t size = 40) {
    std::vector<PhantomSpec> specs;
    for (const auto& name : phantom_preset_names()) specs.push_back(phantom_preset(name, {size, size, size}));
    return specs;
}

/// Random points in the box [lo, hi]^3 (deterministic).
std::vector<Point> random_points(std::size_t count, double lo, double hi, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(lo, hi);
    std::vector<Point> points(count);
    for (auto& p : points) p = {u(rng), u(rng), u(rng)};
    return points;
}

double distance(const Point& a, const Point& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

double sdf(const PhantomSpec& spec, const Point& p) { return phantom_signed_distance(spec, p[0], p[1], p[2]); }

TEST(PhantomTest, BlurIsTheCourseworkFormula) {
    // s(v, w) = 1 if v < -w; (w - v) / (2w) if -w <= v < w; 0 if v >= w.
    EXPECT_EQ(phantom_blur(0, 5), 0.5);
    EXPECT_EQ(phantom_blur(-5, 5), 1.0);
    EXPECT_EQ(phantom_blur(-7, 5), 1.0);
    EXPECT_EQ(phantom_blur(2.5, 5), 0.25);
    EXPECT_EQ(phantom_blur(-2.5, 5), 0.75);
    EXPECT_EQ(phantom_blur(5, 5), 0.0);
    EXPECT_EQ(phantom_blur(9, 5), 0.0);
    // w = 0 is a step, 0.5 on the surface itself.
    EXPECT_EQ(phantom_blur(-1e-9, 0), 1.0);
    EXPECT_EQ(phantom_blur(0, 0), 0.5);
    EXPECT_EQ(phantom_blur(1e-9, 0), 0.0);
}

TEST(PhantomTest, BlurIsMonotone) {
    double previous = phantom_blur(-10, 5);
    for (double v = -10; v <= 10; v += 0.01) {
        const double s = phantom_blur(v, 5);
        EXPECT_LE(s, previous) << "v = " << v;
        EXPECT_GE(s, 0.0);
        EXPECT_LE(s, 1.0);
        previous = s;
    }
}

TEST(PhantomTest, DensityIsHalfExactlyOnTheSurface) {
    // Points on each table-3.1 surface at 128^3, centre 63.5: exactly representable, so the
    // signed distance is exactly 0 and the density exactly 0.5.
    const std::array<std::int64_t, 3> dims{128, 128, 128};
    const double c = 63.5;
    EXPECT_EQ(phantom_density(phantom_preset("sphere", dims), c + 40, c, c), 0.5);
    EXPECT_EQ(phantom_density(phantom_preset("sphere", dims), c, c, c - 40), 0.5);
    EXPECT_EQ(phantom_density(phantom_preset("cube", dims), c + 40, c + 12.25, c - 30), 0.5);
    EXPECT_EQ(phantom_density(phantom_preset("cylinder", dims), c + 40, c, c + 17), 0.5);
    EXPECT_EQ(phantom_density(phantom_preset("cylinder", dims), c + 24, c + 32, c + 60), 0.5);  // cap
    EXPECT_EQ(phantom_density(phantom_preset("torus", dims), c + 44, c, c), 0.5);
    EXPECT_EQ(phantom_density(phantom_preset("cube-minus-sphere", dims), c + 40, c + 35, c), 0.5);  // face
    EXPECT_EQ(phantom_density(phantom_preset("cube-minus-sphere", dims), c + 30, c + 40, c), 0.5);  // hole's edge
    EXPECT_EQ(phantom_density(phantom_preset("cube-minus-sphere", dims), c, c + 30, c + 40), 0.5);
    // Inside and outside.
    EXPECT_EQ(phantom_density(phantom_preset("sphere", dims), c, c, c), 1.0);
    EXPECT_EQ(phantom_density(phantom_preset("sphere", dims), c + 46, c, c), 0.0);
    EXPECT_DOUBLE_EQ(phantom_density(phantom_preset("sphere", dims), c + 42, c, c), 0.3);
    EXPECT_EQ(phantom_density(phantom_preset("cube-minus-sphere", dims), c, c, c), 0.0);  // in the hole
}

TEST(PhantomTest, DensityIsTheBlurOfTheSignedDistance) {
    for (const PhantomSpec& spec : small_presets()) {
        for (const Point& p : random_points(300, -2, 42, 7)) {
            const double d = sdf(spec, p);
            EXPECT_EQ(phantom_density(spec, p[0], p[1], p[2]), phantom_blur(d, spec.blur));
        }
    }
}

/// Central-difference gradient of the signed distance.
Point gradient(const PhantomSpec& spec, const Point& p, double h) {
    Point g{};
    for (int a = 0; a < 3; ++a) {
        Point plus = p, minus = p;
        plus[a] += h;
        minus[a] -= h;
        g[a] = (sdf(spec, plus) - sdf(spec, minus)) / (2 * h);
    }
    return g;
}

TEST(PhantomTest, SignedDistanceIsOneLipschitz) {
    // A 1-Lipschitz function vanishing on the surface is at most the distance to it.
    for (const PhantomSpec& spec : small_presets()) {
        const auto a = random_points(400, -5, 45, 11), b = random_points(400, -5, 45, 12);
        for (std::size_t i = 0; i < a.size(); ++i) {
            Point near = a[i];
            near[i % 3] += 0.01 * (b[i][0] - 20);  // also pairs a fraction of a voxel apart
            EXPECT_LE(std::abs(sdf(spec, a[i]) - sdf(spec, b[i])), distance(a[i], b[i]) * (1 + 1e-12));
            EXPECT_LE(std::abs(sdf(spec, a[i]) - sdf(spec, near)), distance(a[i], near) * (1 + 1e-9) + 1e-12);
        }
    }
}

TEST(PhantomTest, ClosestPointProjectionLandsOnTheSurface) {
    // Moving p by its distance against the gradient reaches the surface: the distance is at
    // least |sdf|. With the Lipschitz test this makes |sdf| the exact distance. Points where the
    // gradient is not unit (on a medial axis, where it jumps) are skipped, and counted.
    for (const PhantomSpec& spec : small_presets()) {
        int checked = 0;
        const auto points = random_points(500, -5, 45, 13);
        for (const Point& p : points) {
            const double d = sdf(spec, p);
            const Point g = gradient(spec, p, 1e-6);
            if (std::abs(std::hypot(g[0], g[1], g[2]) - 1) > 1e-4) continue;
            const Point q{p[0] - d * g[0], p[1] - d * g[1], p[2] - d * g[2]};
            // Central differences with h = 1e-6 carry ~1e-9 error in g, times |d| < 40.
            EXPECT_NEAR(sdf(spec, q), 0.0, 1e-6) << "shape " << static_cast<int>(spec.shape) << " at " << p[0]
                                                 << " " << p[1] << " " << p[2];
            ++checked;
        }
        EXPECT_GT(checked, 450);  // the medial axes have measure zero: almost no point is skipped
    }
}

TEST(PhantomTest, CubeMinusSphereDistanceMatchesBruteForce) {
    // The one shape whose distance is not a textbook formula: compare with the distance to a
    // dense sampling of its surface. Cube of side 16 (h = 8) minus a ball of radius 10: the
    // faces keep the parts outside discs of radius 6, the sphere the part inside the cube.
    PhantomSpec spec;
    spec.shape = PhantomShape::cube_minus_sphere;
    spec.dims = {20, 20, 20};
    spec.centre = Point{0, 0, 0};
    spec.side = 16;
    spec.hole_radius = 10;
    const double h = 8, rs = 10, rho = 6, step = 0.1;
    std::vector<Point> surface;
    for (double u = -h; u <= h + 1e-9; u += step)
        for (double v = -h; v <= h + 1e-9; v += step)
            if (u * u + v * v >= rho * rho)
                for (int n = 0; n < 3; ++n)
                    for (double side : {-h, h}) {
                        Point p{};
                        p[n] = side, p[(n + 1) % 3] = u, p[(n + 2) % 3] = v;
                        surface.push_back(p);
                    }
    const int sphere_points = 200000;  // Fibonacci lattice: spacing sqrt(4 pi rs^2 / N) = 0.08
    for (int i = 0; i < sphere_points; ++i) {
        const double z = 1 - (2 * i + 1.0) / sphere_points, r = std::sqrt(1 - z * z), phi = i * 2.399963229728653;
        const Point p{rs * r * std::cos(phi), rs * r * std::sin(phi), rs * z};
        if (std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])}) <= h) surface.push_back(p);
    }
    for (const Point& p : random_points(200, -12, 12, 17)) {
        double brute = std::numeric_limits<double>::infinity();
        for (const Point& s : surface) brute = std::min(brute, distance(p, s));
        const double exact = sdf(spec, p);
        // The samples lie on the surface, so brute >= |exact|; they are at most ~0.08 apart
        // (faces: grid of 0.1, half-diagonal 0.071; sphere: 0.08), so brute exceeds it by less than 0.1.
        EXPECT_LE(std::abs(exact), brute + 1e-9);
        EXPECT_LE(brute, std::abs(exact) + 0.1);
        const bool inside = std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])}) < h &&
                            std::hypot(p[0], p[1], p[2]) > rs;
        EXPECT_EQ(exact < 0, inside);
    }
}

/// Brute-force integrals of a phantom: jittered sampling (one random point per cell of side
/// 1/8) of the unit cells near the surface; unit cells farther than their half-diagonal plus
/// 2 eps from it are wholly inside or outside (the distance is 1-Lipschitz).
struct Integrals {
    double volume = 0;
    double shell = 0, wide_shell = 0;  ///< volumes of |sdf| < eps and |sdf| < 2 eps
};

Integrals integrate(const PhantomSpec& spec, double eps) {
    const int n = 8;
    const double half_diagonal = std::sqrt(3.0) / 2, sub = 1.0 / n, sub_volume = sub * sub * sub;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> jitter(0, sub);
    Integrals result;
    for (std::int64_t x = -1; x <= spec.dims[0]; ++x)
        for (std::int64_t y = -1; y <= spec.dims[1]; ++y)
            for (std::int64_t z = -1; z <= spec.dims[2]; ++z) {
                const double d = sdf(spec, {double(x), double(y), double(z)});
                if (std::abs(d) > half_diagonal + 2 * eps) {
                    result.volume += d < 0;
                    continue;
                }
                for (int i = 0; i < n * n * n; ++i) {
                    const Point p{x - 0.5 + (i % n) * sub + jitter(rng), y - 0.5 + (i / n % n) * sub + jitter(rng),
                                  z - 0.5 + (i / (n * n)) * sub + jitter(rng)};
                    const double e = sdf(spec, p);
                    result.volume += (e < 0) * sub_volume;
                    result.shell += (std::abs(e) < eps) * sub_volume;
                    result.wide_shell += (std::abs(e) < 2 * eps) * sub_volume;
                }
            }
    return result;
}

TEST(PhantomTest, AreaAndVolumeMatchBruteForce) {
    // Area by the coarea formula (|grad sdf| = 1): S(eps) = shell volume / 2 eps. Edges bias it
    // linearly in eps (cube-minus-sphere's acute 37-degree circle edges: -3% at eps = 0.3), so
    // take Richardson's 2 S(eps) - S(2 eps), which leaves O(eps^2). The jittered sampling's
    // noise is ~0.2% at this size (measured: area within 0.18%, volume within 0.01%), so 0.5%
    // and 0.1% hold with margin; the volume needs no correction.
    const double eps = 0.2;
    for (const PhantomSpec& spec : small_presets(32)) {
        const Integrals in = integrate(spec, eps);
        const double area = 2 * in.shell / (2 * eps) - in.wide_shell / (4 * eps);
        EXPECT_NEAR(in.volume / phantom_volume(spec), 1.0, 0.001) << static_cast<int>(spec.shape);
        EXPECT_NEAR(area / phantom_area(spec), 1.0, 0.005) << static_cast<int>(spec.shape);
    }
}

TEST(PhantomTest, AnalyticAreasAndVolumes) {
    const std::array<std::int64_t, 3> dims{128, 128, 128};
    const double pi = 3.14159265358979323846;
    EXPECT_DOUBLE_EQ(phantom_area(phantom_preset("sphere", dims)), 4 * pi * 1600);
    EXPECT_DOUBLE_EQ(phantom_volume(phantom_preset("cube", dims)), 512000);
    EXPECT_DOUBLE_EQ(phantom_volume(phantom_preset("cylinder", dims)), pi * 1600 * 120);
    // Cube 80 minus ball 50: six caps of height 10 leave the cube.
    const double ball_in_cube = 4 * pi * 125000 / 3 - 6 * pi * 100 * (150 - 10) / 3;
    EXPECT_DOUBLE_EQ(phantom_volume(phantom_preset("cube-minus-sphere", dims)), 512000 - ball_in_cube);
    EXPECT_DOUBLE_EQ(phantom_area(phantom_preset("cube-minus-sphere", dims)),
                     6 * (6400 - pi * 900) + 4 * pi * 2500 - 6 * 2 * pi * 50 * 10);
}

TEST(PhantomTest, PresetsScaleWithTheVolume) {
    EXPECT_EQ(phantom_preset("sphere", {128, 128, 128}).radius, 40);
    EXPECT_EQ(phantom_preset("sphere", {64, 80, 96}).radius, 20);
    const PhantomSpec cylinder = phantom_preset("cylinder", {256, 256, 256});
    EXPECT_EQ(cylinder.radius, 80);
    EXPECT_EQ(cylinder.height, 240);
    EXPECT_EQ(phantom_preset("rotated-cube", {128, 128, 128}).rotation_degrees[1], 20);
    EXPECT_THROW(phantom_preset("dodecahedron", {8, 8, 8}), UsageError);
}

TEST(PhantomTest, RotatedCubeKeepsItsShape) {
    PhantomSpec spec = phantom_preset("rotated-cube", {128, 128, 128});
    const auto centre = spec.centre_or_default();
    EXPECT_LT(sdf(spec, centre), -31.9);  // half the side, 32
    // The corners of the unrotated cube are outside once rotated; the area does not change.
    EXPECT_GT(sdf(spec, {centre[0] + 31, centre[1] + 31, centre[2] + 31}), 0);
    EXPECT_DOUBLE_EQ(phantom_area(spec), 6 * 64.0 * 64.0);
}

TEST(PhantomTest, InvalidSpecsAreRefused) {
    PhantomSpec torus = phantom_preset("torus", {64, 64, 64});
    torus.tube_radius = torus.radius;
    EXPECT_THROW(validate_phantom(torus), UsageError);
    PhantomSpec holed = phantom_preset("cube-minus-sphere", {64, 64, 64});
    holed.hole_radius = holed.side / std::sqrt(2.0);
    EXPECT_THROW(phantom_density(holed, 1, 2, 3), UsageError);
    PhantomSpec blurred;
    blurred.blur = -1;
    EXPECT_THROW(validate_phantom(blurred), UsageError);
    PhantomSpec empty;
    empty.dims = {0, 4, 4};
    EXPECT_THROW(validate_phantom(empty), UsageError);
}

TEST(PhantomTest, NoiseIsSeededAndGaussian) {
    PhantomSpec spec = phantom_preset("sphere", {64, 64, 64});
    spec.noise_sigma = 0.1;
    spec.seed = 42;
    PhantomSpec other = spec;
    other.seed = 43;
    // A block deep inside the sphere, where the density is exactly 1.
    double sum = 0, sum2 = 0;
    int count = 0, differ = 0;
    for (std::int64_t z = 26; z < 38; ++z)
        for (std::int64_t y = 26; y < 38; ++y)
            for (std::int64_t x = 26; x < 38; ++x) {
                const float sample = phantom_sample(spec, x, y, z);
                EXPECT_EQ(sample, phantom_sample(spec, x, y, z));  // same seed, same value
                differ += phantom_sample(other, x, y, z) != sample;
                const double e = sample - 1.0;
                sum += e, sum2 += e * e, ++count;
            }
    const double mean = sum / count, sd = std::sqrt(sum2 / count - mean * mean);
    // 1728 draws: the mean's standard error is 0.1 / 41.6 = 0.0024, the sd's about 1.7%.
    EXPECT_NEAR(mean, 0.0, 0.01);
    EXPECT_NEAR(sd, 0.1, 0.01);
    EXPECT_GT(differ, count * 9 / 10);
}

TEST(PhantomTest, SlicesDoNotDependOnTheThreadCount) {
    PhantomSpec spec = phantom_preset("torus", {37, 29, 23});
    spec.noise_sigma = 0.05;
    std::vector<float> serial(37 * 29), threaded(37 * 29);
    for (std::int64_t z = 0; z < 23; ++z) {
        {
            tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
            fill_phantom_slice(spec, z, serial.data());
        }
        {
            tbb::global_control four(tbb::global_control::max_allowed_parallelism, 4);
            fill_phantom_slice(spec, z, threaded.data());
        }
        ASSERT_EQ(serial, threaded) << "slice " << z;
        EXPECT_EQ(serial[5 * 37 + 7], phantom_sample(spec, 7, 5, z));
    }
}

}  // namespace
}  // namespace vdbmesh
