// mesh_distance(): mesh to mesh and mesh to an analytic surface, and the exact closest point.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "vdbmesh/geometry.h"
#include "test_meshes.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"

namespace vdbmesh {
namespace {

TEST(MeshDistanceTest, ClosestPointOnTriangleInEveryRegion) {
    const detail::Point3 a{0, 0, 0}, b{2, 0, 0}, c{0, 2, 0};
    const auto closest = [&](detail::Point3 p) { return detail::closest_point_on_triangle(p, a, b, c); };
    EXPECT_EQ(closest({0.5, 0.5, 3}), (detail::Point3{0.5, 0.5, 0}));  // face
    EXPECT_EQ(closest({-1, -1, 1}), a);                               // corner regions
    EXPECT_EQ(closest({3, -1, 0}), b);
    EXPECT_EQ(closest({-1, 3, 0}), c);
    EXPECT_EQ(closest({1, -2, 0}), (detail::Point3{1, 0, 0}));         // edge regions
    EXPECT_EQ(closest({-2, 1, 0}), (detail::Point3{0, 1, 0}));
    EXPECT_EQ(closest({2, 2, 0}), (detail::Point3{1, 1, 0}));
}

TEST(MeshDistanceTest, IdenticalMeshesAreAtZero) {
    // Zero up to the double rounding of sampling and of the closest-point computation.
    const DistanceReport d = mesh_distance(test::cube(), test::cube(), 2000);
    EXPECT_LT(d.hausdorff, 1e-12);
    EXPECT_LT(d.mean, 1e-12);
    EXPECT_LT(d.rms, 1e-12);
}

TEST(MeshDistanceTest, ShiftedCubeHasKnownHausdorff) {
    // Shifting the unit cube by 0.25 in z: the bottom face of each is 0.25 from the other, and
    // no point is farther.
    const DistanceReport d = mesh_distance(test::cube(), test::cube({0, 0, 0.25f}), 20000);
    EXPECT_NEAR(d.hausdorff, 0.25, 1e-6);  // float coordinates
    EXPECT_NEAR(d.max_a_to_b, 0.25, 1e-6);
    EXPECT_NEAR(d.max_b_to_a, 0.25, 1e-6);
    EXPECT_GT(d.mean, 0.0);
    EXPECT_LT(d.mean, 0.25);
    EXPECT_GE(d.rms, d.mean);
}

TEST(MeshDistanceTest, ResultDoesNotDependOnThreads) {
    const Mesh a = test::torus(32, 16), b = test::torus(24, 12, 3.1, 0.9);
    const DistanceReport all = mesh_distance(a, b, 5000);
    DistanceReport one;
    {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = mesh_distance(a, b, 5000);
    }
    EXPECT_EQ(all.hausdorff, one.hausdorff);
    EXPECT_EQ(all.mean, one.mean);
    EXPECT_EQ(all.rms, one.rms);
}

TEST(MeshDistanceTest, TorusAgainstItsAnalyticSurface) {
    const double ring = 3, tube = 1, pi = 3.14159265358979323846;
    const int n = 64, m = 32;
    const Mesh mesh = test::torus(n, m, ring, tube);
    const auto signed_distance = [&](double x, double y, double z) {
        return std::hypot(std::hypot(x, y) - ring, z) - tube;
    };
    std::vector<std::array<double, 3>> surface;
    for (int i = 0; i < 200; ++i) {
        for (int j = 0; j < 100; ++j) {
            const double u = 2 * pi * (i + 0.5) / 200, v = 2 * pi * (j + 0.5) / 100;
            surface.push_back({(ring + tube * std::cos(v)) * std::cos(u), (ring + tube * std::cos(v)) * std::sin(u),
                               tube * std::sin(v)});
        }
    }
    const DistanceReport d = mesh_distance(mesh, signed_distance, 20000, surface);
    // The inscribed mesh is at most a chord's sagitta away: about (ring + tube)(1 - cos(pi / n))
    // + tube (1 - cos(pi / m)) = 0.0097 (with float rounding of the vertices, 1e-6).
    const double sagitta = (ring + tube) * (1 - std::cos(pi / n)) + tube * (1 - std::cos(pi / m));
    EXPECT_LT(d.max_a_to_b, sagitta);
    EXPECT_LT(d.max_b_to_a, sagitta);
    EXPECT_GT(d.max_a_to_b, 0.1 * sagitta);
    EXPECT_LT(d.mean, d.hausdorff);
    // Without surface points only the mesh -> surface direction is measured.
    const DistanceReport one_sided = mesh_distance(mesh, signed_distance, 20000);
    EXPECT_EQ(one_sided.max_b_to_a, 0.0);
    EXPECT_EQ(one_sided.mean_a_to_b, d.mean_a_to_b);
    EXPECT_EQ(one_sided.mean, one_sided.mean_a_to_b);
}

TEST(MeshDistanceTest, MeshWithoutAreaThrows) {
    const Mesh flat = test::triangle_soup({{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}}});
    EXPECT_THROW(mesh_distance(flat, test::cube(), 10), Error);
}

}  // namespace
}  // namespace vdbmesh
