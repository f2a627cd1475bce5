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

}  // namespace
}  // namespace vdbmesh::cli
