// mesh_grid(): option checks, dispatch, and OpenVDB's volumeToMesh turned into outward meshes.

#include <gtest/gtest.h>

#include <openvdb/tools/LevelSetSphere.h>
#include <tbb/global_control.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "mesh/marching_cubes.h"
#include "mesh_checks.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/read.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::test {
namespace {

void expect_closed(const Mesh& mesh) {
    ASSERT_FALSE(mesh.triangles.empty());
    const MeshAnalysis report = analyze_mesh(mesh);
    EXPECT_TRUE(report.closed);
    EXPECT_EQ(report.nonmanifold_edges, 0u);
    EXPECT_EQ(report.misoriented_edges, 0u);
}

TEST(MeshGridTest, RejectsBadOptions) {
    auto grid = make_ball(3, {0, 0, 0});
    MeshOptions options = mesh_options(MeshMethod::mc, 0.0);
    options.adaptivity = 1.5;
    EXPECT_THROW(mesh_grid(*grid, options), UsageError);
    options = mesh_options(MeshMethod::dmc, 0.0);
    options.error = -1;
    EXPECT_THROW(mesh_grid(*grid, options), UsageError);
    options = mesh_options(MeshMethod::mc, std::nan(""));
    EXPECT_THROW(mesh_grid(*grid, options), UsageError);
    options = mesh_options(MeshMethod::openvdb, 0.0);
    options.open_boundary = true;
    EXPECT_THROW(mesh_grid(*grid, options), UsageError);
}

TEST(MeshGridTest, DispatchesEachMethod) {
    auto grid = make_ball(6, {0.2, 0.1, 0.4});
    const Mesh mc = mesh_grid(*grid, mesh_options(MeshMethod::mc, 0.0)).mesh;
    const Mesh direct = detail::marching_cubes(*grid, mesh_options(MeshMethod::mc, 0.0));
    EXPECT_EQ(mc.triangles, direct.triangles);
    EXPECT_EQ(mc.vertices, direct.vertices);
    for (MeshMethod method : {MeshMethod::dmc, MeshMethod::openvdb}) {
        const Mesh mesh = mesh_grid(*grid, mesh_options(method, 0.0)).mesh;
        expect_closed(mesh);
        EXPECT_GT(signed_volume(mesh), 0);
    }
}

TEST(MeshGridTest, ReportsSettingsAndPhases) {
    auto grid = make_ball(6, {0.2, 0.1, 0.4});
    MeshOptions options = mesh_options(MeshMethod::openvdb, 0.0, Inside::below);
    options.adaptivity = 0.25;
    const MeshReport vdb = mesh_grid(*grid, options).report;
    EXPECT_EQ(vdb.method, MeshMethod::openvdb);
    EXPECT_EQ(vdb.adaptivity, 0.25);
    EXPECT_EQ(vdb.inside, Inside::below);
    ASSERT_EQ(vdb.phases.size(), 1u);
    EXPECT_EQ(vdb.phases[0].name, "mesh");
    EXPECT_GE(vdb.total_seconds(), 0.0);
    EXPECT_EQ(vdb.refinement_rounds, 0);
    EXPECT_TRUE(vdb.fallbacks.empty());

    options = mesh_options(MeshMethod::dmc, 0.0);
    options.error = 0.5;
    const MeshReport dmc = mesh_grid(*grid, options).report;
    EXPECT_EQ(dmc.method, MeshMethod::dmc);
    EXPECT_EQ(dmc.error, 0.5);
    std::vector<std::string> names;
    for (const MeshPhase& phase : dmc.phases) names.push_back(phase.name);
    ASSERT_GE(names.size(), 2u);
    EXPECT_EQ(names[0], "octree");
    EXPECT_EQ(names[1], "contour");
    EXPECT_TRUE(dmc.fallbacks.empty());
    EXPECT_LT(dmc.refinement_rounds, 32);
    double sum = 0;
    for (const MeshPhase& phase : dmc.phases) sum += phase.seconds;
    EXPECT_DOUBLE_EQ(dmc.total_seconds(), sum);
}

TEST(MeshGridTest, OpenvdbMethodIsClosedAndOutwardOnADensityBall) {
    const double radius = 10;
    auto grid = make_ball(radius, {0.3, 0.2, 0.1});  // grid class unknown: a density
    const Mesh mesh = mesh_grid(*grid, mesh_options(MeshMethod::openvdb, 0.0)).mesh;
    expect_closed(mesh);
    EXPECT_EQ(analyze_mesh(mesh).degenerate_faces, 0u);
    // Vertices at the mean of a cell's edge crossings sit inside the sphere by up to about
    // h^2 / R; as for Marching Cubes, allow area x 0.1 voxels of volume.
    const double exact_volume = 4.0 / 3.0 * kPi * radius * radius * radius;
    EXPECT_NEAR(signed_volume(mesh), exact_volume, 0.1 * 4 * kPi * radius * radius);
}

TEST(MeshGridTest, OpenvdbMethodIsOutwardOnALevelSetWithInsideBelow) {
    const float radius = 5.0f, voxel = 0.25f;
    auto grid = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(radius, openvdb::Vec3f(1, 2, 3), voxel);
    ASSERT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
    const Mesh mesh = mesh_grid(*grid, mesh_options(MeshMethod::openvdb, 0.0, Inside::below)).mesh;
    expect_closed(mesh);
    const double exact_volume = 4.0 / 3.0 * kPi * radius * radius * radius;
    EXPECT_NEAR(signed_volume(mesh), exact_volume, 0.1 * voxel * 4 * kPi * radius * radius);
    // The same level set read as a density (inside above) is the complement: reversed. Not
    // bit for bit: samples at exactly 0 (distance 20 voxels from the centre) are outside both
    // times, which moves a few vertices.
    const Mesh complement = mesh_grid(*grid, mesh_options(MeshMethod::openvdb, 0.0, Inside::above)).mesh;
    EXPECT_NEAR(signed_volume(complement), -signed_volume(mesh), 1e-4 * exact_volume);
}

/// A scan in memory: f(x, y, z) at each voxel of a box of @a dims, identity geometry.
class FieldReader final : public SliceReader {
public:
    FieldReader(std::array<std::int64_t, 3> dims, std::function<float(double, double, double)> f) : f_(std::move(f)) {
        header_.dims = dims;
        header_.type = SampleType::f32;
    }
    const VolumeHeader& header() const override { return header_; }
    void read_slices(std::int64_t slices, float* out) override {
        for (std::int64_t z = next_; z < next_ + slices; ++z)
            for (std::int64_t y = 0; y < header_.dims[1]; ++y)
                for (std::int64_t x = 0; x < header_.dims[0]; ++x) *out++ = f_(double(x), double(y), double(z));
        next_ += slices;
    }
    std::int64_t next_slice() const override { return next_; }

private:
    VolumeHeader header_;
    std::function<float(double, double, double)> f_;
    std::int64_t next_ = 0;
};

TEST(MeshGridTest, OpenvdbMethodWithInsideBelowMeshesTheObjectOfAConvertedScan) {
    // A converted scan's background (beyond its box) lies below every sample: with the inside
    // below, volumeToMesh alone would count it inside, the object being all but the ball.
    const double radius = 8;
    FieldReader reader({32, 32, 32}, [&](double x, double y, double z) {
        return float(std::sqrt((x - 15.6) * (x - 15.6) + (y - 15.3) * (y - 15.3) + (z - 15.1) * (z - 15.1)) - radius);
    });
    ConvertOptions convert;
    convert.iso = 0;
    const auto grid = convert_to_grid(reader, convert);
    const Mesh mesh = mesh_grid(*grid, mesh_options(MeshMethod::openvdb, 0.0, Inside::below)).mesh;
    expect_closed(mesh);
    const double exact_volume = 4.0 / 3.0 * kPi * radius * radius * radius;
    // As for the density ball above: area x 0.1 voxels of volume.
    EXPECT_NEAR(signed_volume(mesh), exact_volume, 0.1 * 4 * kPi * radius * radius);
}

TEST(MeshGridTest, OpenvdbMethodCountsTheIsovalueAsOutside) {
    // f = 10 - max(|i|, |j|, |k|) with isovalue 5: the shell max = 5 equals the isovalue and is
    // outside, so with inside above the surface lies between the shells 4 and 5 (a cube of
    // side about 10), not between 5 and 6 (side about 12). With inside below the object is
    // f < 5 (the shells 6 and beyond, and the background): the mesh bounds a cavity between
    // the shells 5 and 6, wound towards it (negative volume).
    auto grid = make_grid(openvdb::CoordBBox(openvdb::Coord(-12), openvdb::Coord(12)), [](int i, int j, int k) {
        return float(10 - std::max({std::abs(i), std::abs(j), std::abs(k)}));
    }, -2.0f);
    const Mesh above = mesh_grid(*grid, mesh_options(MeshMethod::openvdb, 5.0)).mesh;
    expect_closed(above);
    EXPECT_GT(signed_volume(above), 8.0 * 8 * 8);
    EXPECT_LT(signed_volume(above), 10.0 * 10 * 10);
    const Mesh below = mesh_grid(*grid, mesh_options(MeshMethod::openvdb, 5.0, Inside::below)).mesh;
    expect_closed(below);
    EXPECT_LT(signed_volume(below), -10.0 * 10 * 10);
    EXPECT_GT(signed_volume(below), -12.0 * 12 * 12);
}

TEST(MeshGridTest, EveryMethodGivesTheSameBytesWithOneAndTwoThreads) {
    auto grid = make_ball(20, {0.1, 0.7, 0.3});
    for (MeshMethod method : {MeshMethod::dmc, MeshMethod::mc, MeshMethod::openvdb}) {
        Mesh one, two;
        {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
            one = mesh_grid(*grid, mesh_options(method, 0.0)).mesh;
        }
        {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
            two = mesh_grid(*grid, mesh_options(method, 0.0)).mesh;
        }
        ASSERT_GT(one.triangles.size(), 10000u);
        EXPECT_EQ(one.vertices, two.vertices) << int(method);
        EXPECT_EQ(one.triangles, two.triangles) << int(method);
    }
}

TEST(MeshGridTest, MirroringTransformKeepsNormalsOutward) {
    // An x-flipped scan (negative determinant, as in some NIfTI files) must still give outward
    // triangles in world space.
    auto grid = make_ball(6, {0.2, 0.1, 0.4});
    openvdb::math::Mat4d mirror = openvdb::math::Mat4d::identity();
    mirror(0, 0) = -0.5;
    mirror(1, 1) = 0.5;
    mirror(2, 2) = 2.0;
    grid->setTransform(openvdb::math::Transform::createLinearTransform(mirror));
    for (MeshMethod method : {MeshMethod::dmc, MeshMethod::mc, MeshMethod::openvdb}) {
        const Mesh mesh = mesh_grid(*grid, mesh_options(method, 0.0)).mesh;
        const MeshAnalysis report = analyze_mesh(mesh);
        EXPECT_TRUE(report.closed) << int(method);
        EXPECT_TRUE(report.outward) << int(method);
    }
}

}  // namespace
}  // namespace vdbmesh::test
