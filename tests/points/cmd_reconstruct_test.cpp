#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "point_shapes.h"
#include "test_data.h"
#include "vdbmesh/measure.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/points.h"

namespace vdbmesh::cli {
namespace {

TEST(CmdReconstruct, StlFeedsMeasureAndSection) {
    test::ScratchDir dir;
    PointCloud c = test::sample_shape("cylinder", 6000, 3);
    c.normals.clear();
    write_points_xyz(c, dir / "cyl.xyz");
    const std::string stl = (dir / "cyl.stl").string();
    ASSERT_EQ(run({"reconstruct", (dir / "cyl.xyz").string(), "-o", stl, "--voxel", "0.03", "--quiet"}), kSuccess);
    ASSERT_TRUE(std::filesystem::exists(stl));
    const MeshMeasure m = measure_mesh(read_mesh(stl));
    EXPECT_TRUE(m.report.is_clean());
    EXPECT_NEAR(m.report.volume, 2 * M_PI, 0.03 * 2 * M_PI);
    testing::internal::CaptureStdout();
    EXPECT_EQ(run({"measure", stl, "--json"}), kSuccess);
    EXPECT_NE(testing::internal::GetCapturedStdout().find("\"volume\""), std::string::npos);
    testing::internal::CaptureStdout();
    const int status = run({"section", stl, "--plane", "z=0"});
    const std::string out = testing::internal::GetCapturedStdout();
    EXPECT_EQ(status, kSuccess) << out;
}

TEST(CmdReconstruct, VdbOutputAndJson) {
    test::ScratchDir dir;
    write_points_xyz(test::sample_shape("sphere", 3000, 4), dir / "s.xyz");
    testing::internal::CaptureStdout();
    ASSERT_EQ(run({"reconstruct", (dir / "s.xyz").string(), "-o", (dir / "s.vdb").string(), "--voxel", "0.05", "--json"}), kSuccess);
    EXPECT_NE(testing::internal::GetCapturedStdout().find("\"leaves\""), std::string::npos);
    EXPECT_TRUE(std::filesystem::exists(dir / "s.vdb"));
}

TEST(CmdReconstruct, BadInputFailsAndWritesNothing) {
    test::ScratchDir dir;
    std::ofstream(dir / "bad.xyz") << "0 0 0\n1 2\n";
    testing::internal::CaptureStderr();
    EXPECT_EQ(run({"reconstruct", (dir / "bad.xyz").string(), "-o", (dir / "x.stl").string()}), kRuntimeError);
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("line 2"), std::string::npos) << err;
    EXPECT_FALSE(std::filesystem::exists(dir / "x.stl"));
    testing::internal::CaptureStderr();
    EXPECT_EQ(run({"reconstruct", (dir / "bad.xyz").string(), "-o", (dir / "x.txt").string()}), kUsageError);
    testing::internal::GetCapturedStderr();
}

TEST(CmdClassify, PicksTheRightClass) {
    test::ScratchDir dir;
    write_points_xyz(test::sample_shape("sphere", 3000, 1), dir / "sphere.xyz");
    write_points_xyz(test::sample_shape("cube", 3000, 2), dir / "cube.xyz");
    PointCloud s = test::sample_shape("cube", 2000, 9);
    for (auto& p : s.points) p = {2 * p[1] + 5, -2 * p[0], 2 * p[2] - 1};  // rotated 90 degrees, scaled, moved
    s.normals.clear();
    write_points_xyz(s, dir / "sample.xyz");
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    ASSERT_EQ(run({"classify", (dir / "sample.xyz").string(), "--class", "round=" + (dir / "sphere.xyz").string(), "--class",
                   "flat=" + (dir / "cube.xyz").string(), "--points", "400"}),
              kSuccess);
    testing::internal::GetCapturedStderr();
    EXPECT_EQ(testing::internal::GetCapturedStdout(), "flat\n");
    testing::internal::CaptureStdout();
    ASSERT_EQ(run({"similarity", (dir / "sample.xyz").string(), (dir / "cube.xyz").string(), "--json", "--points", "400"}), kSuccess);
    const std::string json = testing::internal::GetCapturedStdout();
    const nlohmann::json j = nlohmann::json::parse(json);
    EXPECT_NEAR(j["scale"].get<double>(), 0.5, 0.005) << json;
}

}  // namespace
}  // namespace vdbmesh::cli
