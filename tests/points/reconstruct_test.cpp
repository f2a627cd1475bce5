#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "cgal_judge.h"
#include "point_shapes.h"
#include "surface_deviation.h"
#include "test_data.h"
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
    o.rbf.decimate.fraction = 0.2;
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
    // The bounds: every bun_zipper vertex within 0.5% of its diagonal, mean under 0.02%.
    const test::ReferenceToSurface to = test::reference_to_surface(reference, r.mesh);
    EXPECT_LT(to.max_percent, 0.5);
    EXPECT_LT(to.mean_percent, 0.02);
    // The other way, where bun_zipper has surface (not across its holes, which we close): the
    // inward pockets reached 6.3% (1.6 cm, in the head, the far field following the planes of
    // a few points with wrong normals). Measured since: 1.36% inward, 1.01% outward; the bound
    // is that figure with some room, not a specification (the issue sets none this way).
    const test::SurfaceToReference from = test::surface_to_reference(r.mesh, reference);
    EXPECT_LT(from.inward_max_percent, 2.0) << "deepest at " << from.deepest[0] << " " << from.deepest[1] << " " << from.deepest[2];
    EXPECT_LT(from.outward_max_percent, 2.0);
}

}  // namespace
}  // namespace vdbmesh
