// `vdbmesh mesh` run in-process: .vdb and raw scan inputs, the isovalue rules, and no output
// file whenever the command fails.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <openvdb/tools/LevelSetSphere.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cli.h"
#include "mesh/marching_cubes.h"
#include "mesh_checks.h"
#include "test_data.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh::test {
namespace {

/// A ball density written as a .vdb, with the isovalue 0 stored when @a store_iso.
std::filesystem::path write_ball_vdb(const ScratchDir& scratch, bool store_iso) {
    auto grid = make_ball(6, {0.5, 0.25, 0.1});
    if (store_iso) grid->insertMeta(kMetaIsovalue, openvdb::DoubleMetadata(0.0));
    const std::filesystem::path path = scratch / (store_iso ? "ball.vdb" : "ball_no_iso.vdb");
    write_vdb(*grid, path);
    return path;
}

/// A 20^3 u8 raw scan: 200 inside a ball of radius 6, 0 elsewhere.
std::filesystem::path write_ball_raw(const ScratchDir& scratch) {
    std::vector<unsigned char> samples;
    for (int z = 0; z < 20; ++z) {
        for (int y = 0; y < 20; ++y) {
            for (int x = 0; x < 20; ++x) {
                const double r = std::sqrt((x - 9.5) * (x - 9.5) + (y - 9.5) * (y - 9.5) + (z - 9.5) * (z - 9.5));
                samples.push_back(r < 6 ? 200 : 0);
            }
        }
    }
    const std::filesystem::path path = scratch / "ball.raw";
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(samples.data()), std::streamsize(samples.size()));
    return path;
}

TEST(CmdMeshTest, JsonReportsTheSettingsAndTheWrittenMesh) {
    ScratchDir scratch;
    const auto input = write_ball_vdb(scratch, true);
    const auto output = scratch / "ball.stl";
    testing::internal::CaptureStdout();
    const int status = cli::run({"mesh", input.string(), "--error", "0.25", "-o", output.string(), "--json"});
    const nlohmann::json report = nlohmann::json::parse(testing::internal::GetCapturedStdout());
    ASSERT_EQ(status, cli::kSuccess);
    const Mesh written = read_mesh(output);
    EXPECT_EQ(report["method"], "dc");
    EXPECT_EQ(report["error"], 0.25);
    EXPECT_TRUE(report["adaptivity"].is_null());
    EXPECT_EQ(report["triangles"], written.triangles.size());
    EXPECT_EQ(report["vertices"], written.vertices.size());
    EXPECT_GT(report["seconds"].get<double>(), 0.0);
    // What the mesher did: its phases in order, no fallback.
    ASSERT_TRUE(report["phases"].is_array());
    ASSERT_EQ(report["phases"].size(), 5u);
    EXPECT_EQ(report["phases"][0]["name"], "octree");
    EXPECT_EQ(report["phases"][1]["name"], "coarse");
    EXPECT_EQ(report["phases"][2]["name"], "split");
    EXPECT_EQ(report["phases"][3]["name"], "contour");
    EXPECT_EQ(report["phases"][4]["name"], "weld");
    EXPECT_GE(report["phases"][0]["seconds"].get<double>(), 0.0);
    EXPECT_TRUE(report["fallbacks"].is_array());
    EXPECT_TRUE(report["fallbacks"].empty());
}

// Issue 10, point 6: an output name that is not UTF-8 (any bytes are a Linux file name) made
// --json throw after the mesh was written ("invalid UTF-8 byte"), with no report.
TEST(CmdMeshTest, JsonNamesAnOutputThatIsNotUtf8WithReplacementCharacters) {
    ScratchDir scratch;
    const auto input = write_ball_vdb(scratch, true);
    const auto output = scratch / "ball\xff.stl";
    testing::internal::CaptureStdout();
    const int status = cli::run({"mesh", input.string(), "--error", "0.25", "-o", output.string(), "--json"});
    const std::string text = testing::internal::GetCapturedStdout();
    ASSERT_EQ(status, cli::kSuccess);
    EXPECT_TRUE(std::filesystem::exists(output));
    const nlohmann::json report = nlohmann::json::parse(text);  // throws on text that is not UTF-8
    const std::string named = report["output"].get<std::string>();
    EXPECT_NE(named.find("ball\xef\xbf\xbd.stl"), std::string::npos) << named;  // U+FFFD for the 0xff byte
}

TEST(CmdMeshTest, VerifyWritesACleanMeshAndReportsItsCheck) {
    ScratchDir scratch;
    const auto input = write_ball_vdb(scratch, true);
    const auto output = scratch / "ball.stl";
    testing::internal::CaptureStdout();
    const int status = cli::run({"mesh", input.string(), "--error", "0.25", "--verify", "-o", output.string(), "--json"});
    const nlohmann::json report = nlohmann::json::parse(testing::internal::GetCapturedStdout());
    ASSERT_EQ(status, cli::kSuccess);
    EXPECT_TRUE(std::filesystem::exists(output));
    ASSERT_TRUE(report["verified"].is_object());
    EXPECT_EQ(report["verified"]["clean"], true);
    EXPECT_EQ(report["verified"]["triangles"], report["triangles"]);
}

TEST(CmdMeshTest, VerifyRefusesADefectiveMeshWithExitStatusThree) {
    // volumeToMesh at adaptivity 1 self-intersects on the walnut CT (20 pairs, issue 9's table).
    VDBMESH_SHARED_DATA(walnut, "openqvis_walnut_ct/walnut.dat");
    ScratchDir scratch;
    const auto output = scratch / "walnut.stl";
    const int status = cli::run({"mesh", walnut.string(), "--iso", "4084.5", "--method", "openvdb", "--adaptivity", "1",
                                 "--verify", "-o", output.string(), "--quiet"});
    EXPECT_EQ(status, cli::kCheckFailed);
    EXPECT_FALSE(std::filesystem::exists(output));
    // Without --verify the same mesh is written: the meshers do not check themselves.
    EXPECT_EQ(cli::run({"mesh", walnut.string(), "--iso", "4084.5", "--method", "openvdb", "--adaptivity", "1", "-o",
                        output.string(), "--quiet"}),
              cli::kSuccess);
    EXPECT_FALSE(analyze_mesh(read_mesh(output)).is_clean());
}

TEST(CmdMeshTest, MeshesAVdbAtItsStoredIsovalue) {
    ScratchDir scratch;
    const auto input = write_ball_vdb(scratch, true);
    const auto output = scratch / "ball.ply";
    ASSERT_EQ(cli::run({"mesh", input.string(), "--method", "MC", "-o", output.string(), "--quiet"}), cli::kSuccess);
    const Mesh written = read_mesh(output);
    MeshOptions options;
    options.method = MeshMethod::mc;
    const Mesh expected = detail::marching_cubes(*read_vdb(input), options);
    EXPECT_EQ(written.vertices, expected.vertices);  // binary PLY keeps the floats
    EXPECT_EQ(written.triangles, expected.triangles);
}

TEST(CmdMeshTest, EveryMethodWritesAClosedOutwardMesh) {
    ScratchDir scratch;
    const auto input = write_ball_vdb(scratch, true);
    for (const char* method : {"dc", "mc", "openvdb"}) {
        const auto output = scratch / (std::string(method) + ".stl");
        ASSERT_EQ(cli::run({"mesh", input.string(), "--method", method, "-o", output.string(), "-q", "--threads", "2"}),
                  cli::kSuccess) << method;
        const MeshAnalysis report = analyze_mesh(read_mesh(output));
        EXPECT_TRUE(report.closed) << method;
        EXPECT_TRUE(report.outward) << method;
        EXPECT_EQ(report.nonmanifold_edges, 0u) << method;
    }
}

// Dual Marching Cubes was retired (docs/dmc.md): --method dmc still runs, as dc, with a note.
TEST(CmdMeshTest, RetiredDmcMethodRunsDcWithANote) {
    ScratchDir scratch;
    const auto input = write_ball_vdb(scratch, true);
    const auto retired = scratch / "dmc.ply", dc = scratch / "dc.ply";
    testing::internal::CaptureStderr();
    testing::internal::CaptureStdout();
    const int status = cli::run({"mesh", input.string(), "--method", "DMC", "--error", "0.25", "-o", retired.string(), "--json"});
    const std::string json = testing::internal::GetCapturedStdout();
    const std::string note = testing::internal::GetCapturedStderr();
    ASSERT_EQ(status, cli::kSuccess);
    EXPECT_NE(note.find("dmc was retired: it runs dc, see docs/dmc.md"), std::string::npos) << note;
    EXPECT_EQ(nlohmann::json::parse(json)["method"], "dc");
    ASSERT_EQ(cli::run({"mesh", input.string(), "--error", "0.25", "-o", dc.string(), "-q"}), cli::kSuccess);
    const Mesh a = read_mesh(retired), b = read_mesh(dc);
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_EQ(a.triangles, b.triangles);
}

TEST(CmdMeshTest, MeshesARawScanConvertedOnTheFly) {
    ScratchDir scratch;
    const auto input = write_ball_raw(scratch);
    const auto output = scratch / "ball.obj";
    ASSERT_EQ(cli::run({"mesh", input.string(), "--raw-dims", "20,20,20", "--iso", "100", "-o", output.string(), "-q"}),
              cli::kSuccess);
    const MeshAnalysis report = analyze_mesh(read_mesh(output));
    EXPECT_TRUE(report.closed);
    EXPECT_TRUE(report.outward);
    // Samples 200 and 0 around 100: the surface passes half way between the last inside and
    // the first outside samples, within a voxel of the radius-6 sphere.
    EXPECT_GT(report.volume, 4.0 / 3.0 * 3.14159 * 5 * 5 * 5);
    EXPECT_LT(report.volume, 4.0 / 3.0 * 3.14159 * 7 * 7 * 7);
}

TEST(CmdMeshTest, MirroredScanGivesOutwardMeshes) {
    // SPM12's template is stored x-flipped (negative determinant): the winding must be
    // reversed in world space, or every normal points in.
    VDBMESH_SHARED_DATA(input, "nifti_spm12_single_subj_t1/single_subj_T1.nii");
    ScratchDir scratch;
    for (const char* method : {"mc", "openvdb"}) {
        const auto output = scratch / (std::string(method) + ".ply");
        ASSERT_EQ(cli::run({"mesh", input.string(), "--iso", "0.2", "--method", method, "-o", output.string(), "-q"}),
                  cli::kSuccess);
        EXPECT_GT(mesh_integrals(read_mesh(output)).volume, 0) << method;
    }
}

// --memory (issue 28): the same bytes as without it (DC, and Marching Cubes at the default error
// 0 or by --method mc); a limit too small, a malformed size, or volumeToMesh (which meshes only
// whole grids) is refused before any work, nothing written.
TEST(CmdMeshTest, MemoryLimitGivesTheSameBytesOrIsRefused) {
    ScratchDir scratch;
    const auto input = write_ball_raw(scratch);
    const std::vector<std::string> scan = {"mesh", input.string(), "--raw-dims", "20,20,20", "--iso", "100", "-q"};
    auto run_with = [&](const std::vector<std::string>& more) {
        std::vector<std::string> args = scan;
        args.insert(args.end(), more.begin(), more.end());
        return cli::run(args);
    };
    const auto whole = scratch / "whole.ply", bounded = scratch / "bounded.ply";
    ASSERT_EQ(run_with({"-o", whole.string(), "--error", "0.5"}), cli::kSuccess);
    ASSERT_EQ(run_with({"-o", bounded.string(), "--error", "0.5", "--memory", "80M"}), cli::kSuccess);
    auto bytes = [](const std::filesystem::path& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    EXPECT_EQ(bytes(bounded), bytes(whole));
    // STL writes each triangle's corners, which the spill then keeps too: the same bytes.
    const auto whole_stl = scratch / "whole.stl", bounded_stl = scratch / "bounded.stl";
    ASSERT_EQ(run_with({"-o", whole_stl.string(), "--error", "0.5"}), cli::kSuccess);
    ASSERT_EQ(run_with({"-o", bounded_stl.string(), "--error", "0.5", "--memory", "80M"}), cli::kSuccess);
    EXPECT_EQ(bytes(bounded_stl), bytes(whole_stl));
    // The default error 0 (the dual mesh) and --method mc: by bricks too, the same bytes.
    for (const std::vector<std::string>& method : {std::vector<std::string>{}, std::vector<std::string>{"--method", "mc"}}) {
        const auto whole_mc = scratch / "whole_mc.ply", bounded_mc = scratch / "bounded_mc.ply";
        std::vector<std::string> plain = {"-o", whole_mc.string()}, limited = {"-o", bounded_mc.string(), "--memory", "80M"};
        plain.insert(plain.end(), method.begin(), method.end());
        limited.insert(limited.end(), method.begin(), method.end());
        ASSERT_EQ(run_with(plain), cli::kSuccess);
        ASSERT_EQ(run_with(limited), cli::kSuccess);
        EXPECT_EQ(bytes(bounded_mc), bytes(whole_mc)) << (method.empty() ? "error 0" : "--method mc");
    }
    const auto refused = scratch / "refused.ply";
    testing::internal::CaptureStderr();
    EXPECT_EQ(run_with({"-o", refused.string(), "--error", "0.5", "--memory", "1M"}), cli::kUsageError);
    const std::string message = testing::internal::GetCapturedStderr();
    EXPECT_NE(message.find("the smallest limit that works is"), std::string::npos) << message;
    for (const char* size : {"12Q", "-1G", "0", "1K"}) {
        EXPECT_EQ(run_with({"-o", refused.string(), "--error", "0.5", "--memory", size}), cli::kUsageError) << size;
    }
    EXPECT_EQ(run_with({"-o", refused.string(), "--memory", "1G", "--method", "openvdb"}), cli::kUsageError);
    EXPECT_FALSE(std::filesystem::exists(refused));
}

TEST(CmdMeshTest, FailuresLeaveNoOutput) {
    ScratchDir scratch;
    const auto vdb_without_iso = write_ball_vdb(scratch, false);
    const auto raw = write_ball_raw(scratch);
    const auto output = scratch / "out.stl";
    // A .vdb without a stored isovalue, and a scan, need --iso.
    EXPECT_EQ(cli::run({"mesh", vdb_without_iso.string(), "-o", output.string(), "-q"}), cli::kUsageError);
    EXPECT_EQ(cli::run({"mesh", raw.string(), "--raw-dims", "20,20,20", "-o", output.string(), "-q"}), cli::kUsageError);
    // Unknown output format, method, side; adaptivity out of range; open boundary with openvdb.
    EXPECT_EQ(cli::run({"mesh", vdb_without_iso.string(), "--iso", "0", "-o", (scratch / "out.xyz").string(), "-q"}),
              cli::kUsageError);
    EXPECT_EQ(cli::run({"mesh", vdb_without_iso.string(), "--iso", "0", "--method", "fast", "-o", output.string()}),
              cli::kUsageError);
    EXPECT_EQ(cli::run({"mesh", vdb_without_iso.string(), "--iso", "0", "--inside", "left", "-o", output.string()}),
              cli::kUsageError);
    EXPECT_EQ(cli::run({"mesh", vdb_without_iso.string(), "--iso", "0", "--adaptivity", "2", "-o", output.string()}),
              cli::kUsageError);
    EXPECT_EQ(cli::run({"mesh", vdb_without_iso.string(), "--iso", "0", "--method", "openvdb", "--open-boundary", "-o",
                        output.string()}),
              cli::kUsageError);
    // A missing input is a runtime error.
    EXPECT_EQ(cli::run({"mesh", (scratch / "missing.vdb").string(), "--iso", "0", "-o", output.string(), "-q"}),
              cli::kRuntimeError);
    // Nothing but the two inputs: no output, no temporary file left behind.
    const auto entries = std::distance(std::filesystem::directory_iterator(scratch.path()), std::filesystem::directory_iterator());
    EXPECT_EQ(entries, 2);
}

TEST(CmdMeshTest, NoSurfaceAtTheIsovalueIsAnErrorAndKeepsTheOldFile) {
    ScratchDir scratch;
    const auto raw = write_ball_raw(scratch);
    const auto output = scratch / "out.stl";
    std::ofstream(output) << "old";
    // Above every sample (below every sample, the whole scan is inside: its box is the surface).
    EXPECT_EQ(cli::run({"mesh", raw.string(), "--raw-dims", "20,20,20", "--iso", "250", "-o", output.string(), "-q"}),
              cli::kRuntimeError);
    std::ifstream in(output);
    EXPECT_TRUE(std::string(std::istreambuf_iterator<char>(in), {}) == "old");
    EXPECT_EQ(cli::run({"convert", raw.string(), "--raw-dims", "20,20,20", "--iso", "250", "-o",
                        (scratch / "out.vdb").string(), "-q"}),
              cli::kRuntimeError);
    EXPECT_FALSE(std::filesystem::exists(scratch / "out.vdb"));
}

TEST(CmdMeshTest, AVdbMeshedOutsideTheIsovaluesOfItsBandIsAnError) {
    ScratchDir scratch;
    const auto raw = write_ball_raw(scratch);
    const auto at_60 = scratch / "at_60.vdb", range = scratch / "range.vdb";
    ASSERT_EQ(cli::run({"convert", raw.string(), "--raw-dims", "20,20,20", "--iso", "60", "-o", at_60.string(), "-q"}),
              cli::kSuccess);
    ASSERT_EQ(cli::run({"convert", raw.string(), "--raw-dims", "20,20,20", "--iso-range", "50,150", "-o", range.string(),
                        "-q"}),
              cli::kSuccess);
    const auto output = scratch / "out.stl";
    EXPECT_EQ(cli::run({"mesh", at_60.string(), "--iso", "150", "-o", output.string(), "-q"}), cli::kRuntimeError);
    EXPECT_FALSE(std::filesystem::exists(output));
    EXPECT_EQ(cli::run({"mesh", range.string(), "--iso", "160", "-o", output.string(), "-q"}), cli::kRuntimeError);
    EXPECT_EQ(cli::run({"mesh", range.string(), "--iso", "150", "-o", output.string(), "-q"}), cli::kSuccess);
    EXPECT_EQ(cli::run({"mesh", at_60.string(), "--iso", "60", "-o", output.string(), "-q"}), cli::kSuccess);
}

TEST(CmdMeshTest, ALevelSetVdbIsMeshedAtZeroWithTheInsideBelow) {
    ScratchDir scratch;
    const auto input = scratch / "sphere.vdb";
    write_vdb(*openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(6.0f, openvdb::Vec3f(0.5f), 1.0f), input);
    const auto output = scratch / "sphere.stl";
    ASSERT_EQ(cli::run({"mesh", input.string(), "-o", output.string(), "-q"}), cli::kSuccess);
    const MeshAnalysis report = analyze_mesh(read_mesh(output));
    EXPECT_TRUE(report.closed);
    EXPECT_TRUE(report.outward);
    EXPECT_NEAR(report.volume, 4.0 / 3.0 * 3.14159 * 6 * 6 * 6, 30.0);
    // An explicit side still wins: the same surface, inside out.
    ASSERT_EQ(cli::run({"mesh", input.string(), "--inside", "above", "-o", output.string(), "-q"}), cli::kSuccess);
    EXPECT_LT(mesh_integrals(read_mesh(output)).volume, 0);
}

}  // namespace
}  // namespace vdbmesh::test
