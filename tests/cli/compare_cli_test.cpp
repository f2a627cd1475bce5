// `vdbmesh compare`: the JSON report's keys and the SVG chart, on a small phantom.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "test_data.h"

namespace vdbmesh::cli {
namespace {

TEST(CompareCliTest, JsonHasEveryKeyAndPlotIsWritten) {
    const test::ScratchDir dir;
    const std::string json = (dir / "report.json").string(), svg = (dir / "curve.svg").string();
    testing::internal::CaptureStdout();
    ASSERT_EQ(run({"compare", "--phantom", "sphere", "--size", "32", "--error", "0,0.25", "--adaptivity", "0,1",
                   "--samples", "2000", "--json", json, "--plot", svg, "--quiet", "--threads", "2"}),
              kSuccess);
    const std::string table = testing::internal::GetCapturedStdout();
    EXPECT_NE(table.find("openvdb"), std::string::npos) << table;

    std::ifstream in(json);
    const nlohmann::json report = nlohmann::json::parse(in);
    EXPECT_EQ(report["grid"]["truth"], "exact phantom surface");
    EXPECT_GT(report["grid"]["active_voxels"].get<long>(), 0);
    // 2 DC, MC, the dual surface (adaptivity 0 is asked), 2 volumeToMesh, 2 budgets at their counts, DC --sharp at 0.25
    ASSERT_EQ(report["meshes"].size(), 9u);
    for (const char* key : {"method", "error", "adaptivity", "triangle_budget", "seconds", "triangles", "vertices", "hausdorff_voxels",
                            "mean_distance_voxels", "self_intersecting_pairs", "closed", "manifold", "normal_mean_deg",
                            "normal_p95_deg", "boundary_edges", "genus", "area", "volume", "min_angle_deg", "phases",
                            "same_mesh_as"}) {
        for (const auto& mesh : report["meshes"]) EXPECT_TRUE(mesh.contains(key)) << key;
    }
    EXPECT_EQ(report["meshes"][0]["method"], "dc");
    EXPECT_EQ(report["meshes"][0]["error"], 0.0);
    EXPECT_TRUE(report["meshes"][0]["adaptivity"].is_null());
    EXPECT_EQ(report["meshes"][2]["method"], "mc");
    EXPECT_EQ(report["meshes"][3]["method"], "dual");
    EXPECT_TRUE(report["meshes"][3]["clean"].get<bool>());
    EXPECT_EQ(report["meshes"][5]["adaptivity"], 1.0);
    // DC at error 0 is MC: the MC row names it; DC at 0.25 reports its five phases.
    EXPECT_EQ(report["meshes"][2]["same_mesh_as"], 0);
    EXPECT_TRUE(report["meshes"][1]["same_mesh_as"].is_null());
    ASSERT_EQ(report["meshes"][1]["phases"].size(), 5u);
    EXPECT_EQ(report["meshes"][1]["phases"][0]["name"], "octree");
    // The budget rows (`mesh --triangles`), one per volumeToMesh mesh, at most its triangles and clean.
    for (const std::size_t i : {6u, 7u}) {
        const auto& budget = report["meshes"][i];
        const auto& openvdb = report["meshes"][i - 2];
        EXPECT_EQ(budget["method"], "dc");
        EXPECT_TRUE(budget["error"].is_null());
        EXPECT_EQ(budget["triangle_budget"], openvdb["triangles"]);
        EXPECT_LE(budget["triangles"].get<double>(), openvdb["triangles"].get<double>());
        EXPECT_TRUE(budget["clean"].get<bool>());
    }
    EXPECT_NE(table.find("<= "), std::string::npos) << table;
    // Under the table, and in the JSON, which rows beat each volumeToMesh row (issue 29, item 5).
    EXPECT_NE(table.find("beaten on every count"), std::string::npos) << table;
    ASSERT_EQ(report["dominance"].size(), 2u);
    EXPECT_EQ(report["dominance"][1]["volume_to_mesh"], 5);
    for (const auto& d : report["dominance"])
        for (const auto& i : d["with_time"]) EXPECT_NE(report["meshes"][i.get<std::size_t>()]["method"], "openvdb");
    // On a phantom, DC --sharp at each error above 0, last (issue 29, item 5).
    EXPECT_EQ(report["meshes"][8]["error"], 0.25);
    EXPECT_EQ(report["meshes"][8]["sharp"], true);
    EXPECT_FALSE(report["meshes"][1]["sharp"].get<bool>());
    EXPECT_TRUE(report["meshes"][8]["clean"].get<bool>());
    EXPECT_NE(table.find("sharp 0.25"), std::string::npos) << table;

    std::ifstream plot(svg);
    const std::string text((std::istreambuf_iterator<char>(plot)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("<svg"), std::string::npos);
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n') > 10, true);
    EXPECT_NE(text.find("volumeToMesh"), std::string::npos);
    EXPECT_NE(text.find("<polyline"), std::string::npos);
}

// --decimate: rows of the error-0 mesh decimated by decimate_mesh(), after the others, at the
// triangle counts asked for, still closed and manifold, and drawn as their own series.
TEST(CompareCliTest, DecimateAddsRowsOfTheDecimatedErrorZeroMesh) {
    const test::ScratchDir dir;
    const std::string json = (dir / "report.json").string(), svg = (dir / "curve.svg").string();
    testing::internal::CaptureStdout();
    ASSERT_EQ(run({"compare", "--phantom", "sphere", "--size", "32", "--error", "0", "--adaptivity", "1", "--no-budget", "--decimate",
                   "0.5,0.2", "--samples", "2000", "--json", json, "--plot", svg, "--quiet"}),
              kSuccess);
    const std::string table = testing::internal::GetCapturedStdout();
    EXPECT_NE(table.find("dec 0.2"), std::string::npos) << table;

    std::ifstream in(json);
    const nlohmann::json report = nlohmann::json::parse(in);
    ASSERT_EQ(report["meshes"].size(), 5u);  // DC 0, MC, volumeToMesh 1, two decimated (--no-budget: no budget row)
    const auto& full = report["meshes"][0];
    EXPECT_TRUE(full["decimate"].is_null());
    EXPECT_TRUE(full["decimate_seconds"].is_null());
    const double full_triangles = full["triangles"];
    for (const std::size_t i : {3u, 4u}) {
        const auto& row = report["meshes"][i];
        const double keep = i == 3 ? 0.5 : 0.2;
        EXPECT_EQ(row["method"], "dc");
        EXPECT_EQ(row["error"], 0.0);
        EXPECT_EQ(row["decimate"], keep);
        EXPECT_GE(row["decimate_seconds"].get<double>(), 0.0);
        EXPECT_GE(row["seconds"].get<double>(), row["decimate_seconds"].get<double>());
        // decimate_mesh stops at ceil(keep * triangles); a smooth sphere refuses few collapses.
        EXPECT_LE(row["triangles"].get<double>(), std::ceil(keep * full_triangles));
        EXPECT_GE(row["triangles"].get<double>(), 0.9 * keep * full_triangles);
        EXPECT_TRUE(row["closed"].get<bool>());
        EXPECT_TRUE(row["manifold"].get<bool>());
        EXPECT_EQ(row["self_intersecting_pairs"], 0);
        // Coarser than the full mesh, but still near the sphere (voxels).
        EXPECT_GT(row["hausdorff_voxels"].get<double>(), full["hausdorff_voxels"].get<double>());
        EXPECT_LT(row["hausdorff_voxels"].get<double>(), 1.0);
        EXPECT_TRUE(row["same_mesh_as"].is_null());
    }
    std::ifstream plot(svg);
    const std::string text((std::istreambuf_iterator<char>(plot)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("DC + decimate"), std::string::npos);
}

TEST(CompareCliTest, ADecimateShareOutsideZeroToOneIsRefused) {
    for (const char* shares : {"0.5,1.5", "0", "-0.2"})
        EXPECT_EQ(run({"compare", "--phantom", "sphere", "--size", "16", "--decimate", shares, "--quiet"}), kUsageError) << shares;
}

TEST(CompareCliTest, APlotNotNamedSvgIsRefusedBeforeAnyWork) {
    test::ScratchDir dir;
    EXPECT_EQ(run({"compare", "--phantom", "sphere", "--size", "16", "--plot", (dir / "p.png").string(), "--quiet"}), kUsageError);
    EXPECT_FALSE(std::filesystem::exists(dir / "p.png"));
}

// DMC was retired (docs/dmc.md): its option is refused, naming the one that gives DC's errors.
TEST(CompareCliTest, TheRetiredDmcErrorIsAUsageErrorNamingError) {
    testing::internal::CaptureStderr();
    const int status = run({"compare", "--phantom", "sphere", "--size", "16", "--dmc-error", "0.5", "--quiet"});
    const std::string message = testing::internal::GetCapturedStderr();
    EXPECT_EQ(status, kUsageError);
    EXPECT_NE(message.find("--dmc-error: dmc was retired"), std::string::npos) << message;
    EXPECT_NE(message.find("with --error"), std::string::npos) << message;
}

TEST(CompareCliTest, ScanWithoutIsoIsAUsageError) {
    EXPECT_EQ(run({"compare", test::testdata("sphere_phantom.nii.gz").string(), "--quiet"}), kUsageError);
}

}  // namespace
}  // namespace vdbmesh::cli
