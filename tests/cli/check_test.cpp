// `vdbmesh check`: exit statuses and the JSON report.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "test_data.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh::cli {
namespace {

Mesh unit_cube() {
    Mesh mesh;
    for (int i = 0; i < 8; ++i) mesh.vertices.push_back({float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        mesh.triangles.push_back({q[0], q[1], q[2]});
        mesh.triangles.push_back({q[0], q[2], q[3]});
    }
    return mesh;
}

TEST(CheckTest, CleanMeshExitsZero) {
    const test::ScratchDir dir;
    write_mesh(unit_cube(), dir / "cube.stl");
    testing::internal::CaptureStdout();
    EXPECT_EQ(run({"check", (dir / "cube.stl").string()}), kSuccess);
    const std::string out = testing::internal::GetCapturedStdout();
    EXPECT_NE(out.find("self_intersecting_pairs"), std::string::npos) << out;
}

TEST(CheckTest, MeshWithAHoleExitsThree) {
    const test::ScratchDir dir;
    Mesh mesh = unit_cube();
    mesh.triangles.pop_back();
    write_mesh(mesh, dir / "open.ply");
    testing::internal::CaptureStdout();
    EXPECT_EQ(run({"check", (dir / "open.ply").string()}), kCheckFailed);
    testing::internal::GetCapturedStdout();
}

TEST(CheckTest, UnreadableMeshExitsOne) {
    const test::ScratchDir dir;
    EXPECT_EQ(run({"check", (dir / "missing.stl").string()}), kRuntimeError);
}

TEST(CheckTest, MissingArgumentIsUsageError) { EXPECT_EQ(run({"check"}), kUsageError); }

TEST(CheckTest, JsonHasEveryKey) {
    const test::ScratchDir dir;
    write_mesh(unit_cube(), dir / "cube.obj");
    write_mesh(unit_cube(), dir / "ref.stl");
    testing::internal::CaptureStdout();
    EXPECT_EQ(run({"check", (dir / "cube.obj").string(), "--ref", (dir / "ref.stl").string(), "--samples", "500",
                   "--json"}),
              kSuccess);
    const std::string out = testing::internal::GetCapturedStdout();
    const nlohmann::json j = nlohmann::json::parse(out);
    for (const char* key : {"triangles", "vertices", "boundary_edges", "nonmanifold_edges", "nonmanifold_vertices",
                            "degenerate_faces", "self_intersecting_pairs", "components", "genus", "closed", "outward",
                            "area", "volume", "min_angle_deg", "hausdorff", "mean_distance"}) {
        EXPECT_TRUE(j.contains(key)) << key;
    }
    EXPECT_EQ(j["triangles"], 12);
    EXPECT_EQ(j["genus"], 0);
    EXPECT_EQ(j["closed"], true);
    EXPECT_DOUBLE_EQ(j["volume"].get<double>(), 1.0);
    EXPECT_LT(j["hausdorff"].get<double>(), 1e-12);  // double rounding of the closest points
}

/// Runs `vdbmesh check` with @a args; returns its exit status and stdout.
std::pair<int, std::string> run_check(std::vector<std::string> args) {
    args.insert(args.begin(), "check");
    testing::internal::CaptureStdout();
    const int status = run(args);
    return {status, testing::internal::GetCapturedStdout()};
}

TEST(CheckTest, BoundedCheckReportsTheSameJsonButTheTwoFiguresItCannotCount) {
    const test::ScratchDir dir;
    Mesh mesh = unit_cube();
    mesh.triangles.pop_back();  // a hole
    std::swap(mesh.triangles[0][1], mesh.triangles[0][2]);  // a flipped face
    for (const char* name : {"open.ply", "open.stl", "open.obj"}) {
        write_mesh(mesh, dir / name);
        const auto [whole_status, whole_text] = run_check({(dir / name).string(), "--json"});
        const auto [bounded_status, bounded_text] = run_check({(dir / name).string(), "--json", "--memory", "128M"});
        EXPECT_EQ(whole_status, kCheckFailed) << name;
        EXPECT_EQ(bounded_status, kCheckFailed) << name;
        nlohmann::json whole = nlohmann::json::parse(whole_text), bounded = nlohmann::json::parse(bounded_text);
        for (const char* key : {"self_intersecting_pairs", "negative_components"}) {
            EXPECT_TRUE(bounded.at(key).is_null()) << name << " " << key;
            whole.erase(key), bounded.erase(key);
        }
        EXPECT_EQ(bounded, whole) << name;
        EXPECT_GT(bounded["misoriented_edges"].get<int>(), 0) << name;
    }
}

TEST(CheckTest, BoundedCheckOfACleanMeshExitsZeroAndSaysWhatItDidNotCheck) {
    const test::ScratchDir dir;
    write_mesh(unit_cube(), dir / "cube.ply");
    const auto [status, text] = run_check({(dir / "cube.ply").string(), "--memory", "128M"});
    EXPECT_EQ(status, kSuccess);
    EXPECT_NE(text.find("not checked in bounded mode"), std::string::npos) << text;
    EXPECT_NE(text.find("closed                  true"), std::string::npos) << text;
}

TEST(CheckTest, BoundedCheckRefusesALimitTooSmallNamingTheSmallestThatWorks) {
    const test::ScratchDir dir;
    write_mesh(unit_cube(), dir / "cube.ply");
    testing::internal::CaptureStderr();
    EXPECT_EQ(run({"check", (dir / "cube.ply").string(), "--memory", "1M"}), kUsageError);
    const std::string error = testing::internal::GetCapturedStderr();
    EXPECT_NE(error.find("the smallest limit that works is"), std::string::npos) << error;
    EXPECT_EQ(run({"check", (dir / "cube.ply").string(), "--memory", "64Q"}), kUsageError);
    EXPECT_EQ(run({"check", (dir / "cube.ply").string(), "--memory", "128M", "--ref", (dir / "cube.ply").string()}), kUsageError);
}

}  // namespace
}  // namespace vdbmesh::cli
