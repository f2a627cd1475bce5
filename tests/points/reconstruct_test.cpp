#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numeric>

#include "cgal_judge.h"
#include "point_shapes.h"
#include "test_data.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/points.h"

namespace vdbmesh {
namespace {

TEST(Reconstruct, SphereWithoutNormalsIsCleanAndAccurate) {
    PointCloud c = test::sample_shape("sphere", 5000, 11);
    c.normals.clear();
    ReconstructOptions o;
    o.sample.voxel = 0.02;
    const Reconstruction r = reconstruct(c, o);
    const test::CgalVerdict v = test::judge_with_cgal(r.mesh);
    EXPECT_TRUE(v.clean()) << v.describe();
    EXPECT_NEAR(v.volume, 4.0 / 3.0 * M_PI, 0.02 * 4.0 / 3.0 * M_PI);
    double worst = 0;
    for (const auto& p : r.mesh.vertices) worst = std::max(worst, std::abs(std::hypot(p[0], p[1], p[2]) - 1.0));
    EXPECT_LT(worst, 0.01);
}

TEST(Reconstruct, TorusAndCubeMinusSphereAreClean) {
    for (const std::string shape : {"torus", "cube_minus_sphere"}) {
        const PointCloud c = test::sample_shape(shape, 20000, 12);
        ReconstructOptions o;
        o.sample.voxel = 0.02;
        const Reconstruction r = reconstruct(c, o);
        const test::CgalVerdict v = test::judge_with_cgal(r.mesh);
        EXPECT_TRUE(v.clean()) << shape << ": " << v.describe();
        const double expected = shape == "torus" ? 2 * M_PI * M_PI * 1.0 * 0.4 * 0.4 : 8.0 - M_PI / 6 * 0.9 * 0.9 * 0.9;
        EXPECT_NEAR(v.volume, expected, 0.03 * expected) << shape;
    }
}

TEST(Reconstruct, SameResultForAnyThreadCount) {
    const PointCloud c = test::sample_shape("torus", 8000, 13);
    ReconstructOptions o;
    o.sample.voxel = 0.04;
    o.decimate = 0.2;
    const Reconstruction a = reconstruct(c, o);
    Reconstruction b;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        b = reconstruct(c, o);
    }
    EXPECT_EQ(a.mesh.vertices, b.mesh.vertices);
    EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
}

// The figure of issue 13 (accuracy, not time: timings are in bench/points_bench.cpp).
TEST(Reconstruct, StanfordBunnyScansMatchBunZipper) {
    VDBMESH_SHARED_DATA(conf, "pointcloud_stanford_bunny_scans/data/bun.conf");
    VDBMESH_SHARED_DATA(zipper, "pointcloud_stanford_bunny_scans/reconstruction/bun_zipper.ply");
    ReconstructOptions o;
    o.sample.voxel = 0.0005;
    const Reconstruction r = reconstruct(read_points(conf), o);
    const test::CgalVerdict v = test::judge_with_cgal(r.mesh);
    EXPECT_TRUE(v.clean()) << v.describe();
    const Mesh reference = read_mesh(zipper);
    std::vector<std::uint32_t> all(r.mesh.triangles.size());
    std::iota(all.begin(), all.end(), 0u);
    const detail::TriangleBvh bvh(r.mesh, all);
    std::array<double, 3> lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
    for (const auto& p : reference.vertices)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], double(p[a])), hi[a] = std::max(hi[a], double(p[a]));
    const double diagonal = std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    double worst = 0, sum = 0;
    for (const auto& p : reference.vertices) {
        const double d = std::sqrt(bvh.closest_point(detail::Point3{p[0], p[1], p[2]}).distance_squared);
        worst = std::max(worst, d);
        sum += d;
    }
    EXPECT_LT(worst / diagonal, 0.005);
    EXPECT_LT(sum / double(reference.vertices.size()) / diagonal, 0.0002);
}

}  // namespace
}  // namespace vdbmesh
