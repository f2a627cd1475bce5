// --memory beyond mesh and check (issue 28 item 2): `measure` and `section` within SIZE give
// what they give without it, on a phantom and a real scan (meshed by bricks at the same
// --error) and on mesh files; a limit too small is exit 2 naming the smallest that works, with
// nothing written.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <vector>

#include "cli.h"
#include "concat_args.h"
#include "test_data.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh::cli {
namespace {

struct OutAndErr {
    int status;
    std::string out, err;
};

OutAndErr run_capturing_both(const std::vector<std::string>& args) {
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    const int status = run(args);
    std::string out = testing::internal::GetCapturedStdout();
    return {status, out, testing::internal::GetCapturedStderr()};
}

/// The limit a refusal names ("the smallest limit that works is 71M"), in bytes; 0 when none.
std::uint64_t named_smallest(const std::string& message) {
    std::smatch match;
    if (!std::regex_search(message, match, std::regex("smallest limit that (could )?works? is ([0-9]+)M"))) return 0;
    return std::stoull(match[2]) << 20;
}

/// Every figure of `measure --json` with and without --memory: the same but the components'
/// area and volume, summed in another order (tests/analysis/measure_stream_test.cpp: to 1e-9
/// of the whole's).
void expect_same_measure(const nlohmann::json& whole, const nlohmann::json& bounded) {
    for (const auto& [key, value] : whole.items()) {
        if (key != "components") EXPECT_EQ(bounded[key], value) << key;
    }
    ASSERT_EQ(bounded["components"].size(), whole["components"].size());
    const double volume = std::abs(whole["volume"].get<double>()), area = whole["area"];
    for (std::size_t i = 0; i < whole["components"].size(); ++i) {
        const auto &w = whole["components"][i], &b = bounded["components"][i];
        EXPECT_EQ(b["triangles"], w["triangles"]) << i;
        EXPECT_NEAR(b["volume"].get<double>(), w["volume"].get<double>(), 1e-9 * volume) << i;
        EXPECT_NEAR(b["area"].get<double>(), w["area"].get<double>(), 1e-9 * area) << i;
    }
}

/// measure --json of @a args with and without --memory @a memory, compared.
void expect_bounded_measure_is_whole(const std::vector<std::string>& args, const std::string& memory) {
    const OutAndErr whole = run_capturing_both(concat({"measure"}, concat(args, {"--json", "-q"})));
    ASSERT_EQ(whole.status, kSuccess) << whole.err;
    const OutAndErr bounded = run_capturing_both(concat({"measure"}, concat(args, {"--json", "-q", "--memory", memory})));
    ASSERT_EQ(bounded.status, kSuccess) << bounded.err;
    expect_same_measure(nlohmann::json::parse(whole.out), nlohmann::json::parse(bounded.out));
}

std::filesystem::path write_torus_phantom(const test::ScratchDir& dir) {
    const std::filesystem::path path = dir / "torus.nii";
    EXPECT_EQ(run({"phantom", "torus", "--size", "64", "-o", path.string(), "-q"}), kSuccess);
    return path;
}

TEST(MeasureMemoryTest, PhantomScanMeshedByBricksGivesTheWholeMeasure) {
    const test::ScratchDir dir;
    const std::filesystem::path torus = write_torus_phantom(dir);
    expect_bounded_measure_is_whole({torus.string(), "--iso", "0.5", "--error", "0.25"}, "128M");
    expect_bounded_measure_is_whole({torus.string(), "--iso", "0.5"}, "128M");  // error 0: Marching Cubes by bricks
}

TEST(MeasureMemoryTest, RealScanMeshedByBricksGivesTheWholeMeasure) {
    VDBMESH_SHARED_DATA(head, "raw_vtk_headsq/headsq_64x64x93_int16le.raw");
    expect_bounded_measure_is_whole({head.string(), "--raw-dims", "64,64,93", "--raw-type", "i16", "--spacing", "3.2,3.2,1.5", "--iso",
                                     "1000.5", "--error", "0.25"},
                                    "128M");
}

TEST(MeasureMemoryTest, RealMeshFileGivesTheWholeMeasure) {
    VDBMESH_SHARED_DATA(zipper, "pointcloud_stanford_bunny_scans/reconstruction/bun_zipper.ply");
    expect_bounded_measure_is_whole({zipper.string()}, "128M");
}

TEST(MeasureMemoryTest, LimitTooSmallIsUsageErrorNamingTheSmallest) {
    VDBMESH_SHARED_DATA(zipper, "pointcloud_stanford_bunny_scans/reconstruction/bun_zipper.ply");
    const OutAndErr refused = run_capturing_both({"measure", zipper.string(), "--memory", "1M", "--json"});
    EXPECT_EQ(refused.status, kUsageError);
    EXPECT_TRUE(refused.out.empty()) << refused.out;
    const std::uint64_t smallest = named_smallest(refused.err);
    ASSERT_GT(smallest, 0u) << refused.err;
    EXPECT_EQ(run_capturing_both({"measure", zipper.string(), "--memory", std::to_string((smallest >> 20) - 1) + "M", "-q"}).status, kUsageError);
    EXPECT_EQ(run_capturing_both({"measure", zipper.string(), "--memory", std::to_string(smallest >> 20) + "M", "-q"}).status, kSuccess);
}

TEST(MeasureMemoryTest, ScanLimitsAndOptionsTheBricksCannotTakeAreRefused) {
    const test::ScratchDir dir;
    const std::string torus = write_torus_phantom(dir).string();
    const OutAndErr tiny = run_capturing_both({"measure", torus, "--iso", "0.5", "--error", "0.25", "--memory", "1M"});
    EXPECT_EQ(tiny.status, kUsageError);
    EXPECT_GT(named_smallest(tiny.err), 0u) << tiny.err;
    EXPECT_EQ(run_capturing_both({"measure", torus, "--iso", "0.5", "--error", "0.25", "--refine", "--memory", "128M"}).status, kUsageError);
}

/// view --memory: what it cannot bound is refused before anything is read or served (exit 2,
/// naming why): a mesh file (shown whole), a label map, a scan without --iso (its survey needs
/// the surface), and a limit below the program and one close-up's read.
TEST(ViewMemoryTest, WhatTheLimitCannotBoundIsRefusedBeforeServing) {
    const test::ScratchDir dir;
    const std::string torus = write_torus_phantom(dir).string();
    ASSERT_EQ(run_capturing_both({"mesh", torus, "--iso", "0.5", "-o", (dir / "torus.stl").string(), "-q"}).status, kSuccess);
    const std::vector<std::pair<std::vector<std::string>, std::string>> refusals = {
        {{"view", (dir / "torus.stl").string(), "--memory", "1G", "--no-open"}, "a mesh file is shown whole"},
        {{"view", torus, "--labels", "all", "--memory", "1G", "--no-open"}, "not with --labels"},
        {{"view", torus, "--memory", "1G", "--no-open"}, "--iso: required to view a scan with --memory"},
        {{"view", torus, "--iso", "0.5", "--memory", "300M", "--no-open"}, "the smallest limit that could work is 320M"},
    };
    for (const auto& [args, why] : refusals) {
        const OutAndErr refused = run_capturing_both(args);
        EXPECT_EQ(refused.status, kUsageError) << args[1] << " " << args[2];
        EXPECT_NE(refused.err.find(why), std::string::npos) << refused.err;
    }
}

/// section --json of @a args with and without --memory @a memory: the same bytes (edges named by
/// vertex numbers both ways: SectionStream).
void expect_bounded_section_is_whole(const std::vector<std::string>& args, const std::string& memory) {
    const OutAndErr whole = run_capturing_both(concat({"section"}, concat(args, {"--json", "-q"})));
    ASSERT_EQ(whole.status, kSuccess) << whole.err;
    const OutAndErr bounded = run_capturing_both(concat({"section"}, concat(args, {"--json", "-q", "--memory", memory})));
    ASSERT_EQ(bounded.status, kSuccess) << bounded.err;
    EXPECT_EQ(bounded.out, whole.out);
    EXPECT_GT(nlohmann::json::parse(whole.out)["sections"][0]["area"].get<double>(), 0);
}

TEST(SectionMemoryTest, PhantomScanMeshedByBricksGivesTheWholeSections) {
    const test::ScratchDir dir;
    const std::filesystem::path torus = write_torus_phantom(dir);
    expect_bounded_section_is_whole({torus.string(), "--iso", "0.5", "--error", "0.25", "--plane", "z=32", "--planes", "x=20:40:5"}, "128M");
    expect_bounded_section_is_whole({torus.string(), "--iso", "0.5", "--plane", "z=32"}, "128M");  // error 0: Marching Cubes by bricks
}

TEST(SectionMemoryTest, RealScanMeshedByBricksGivesTheWholeSections) {
    VDBMESH_SHARED_DATA(head, "raw_vtk_headsq/headsq_64x64x93_int16le.raw");
    expect_bounded_section_is_whole({head.string(), "--raw-dims", "64,64,93", "--raw-type", "i16", "--spacing", "3.2,3.2,1.5", "--iso",
                                     "1000.5", "--error", "0.25", "--planes", "z=20:120:25"},
                                    "128M");
}

TEST(SectionMemoryTest, LimitTooSmallIsUsageErrorWithNothingWritten) {
    VDBMESH_SHARED_DATA(zipper, "pointcloud_stanford_bunny_scans/reconstruction/bun_zipper.ply");
    const test::ScratchDir dir;
    const std::string svg = (dir / "cut.svg").string();
    const OutAndErr refused = run_capturing_both({"section", zipper.string(), "--plane", "y=0.1", "--svg", svg, "--memory", "1M"});
    EXPECT_EQ(refused.status, kUsageError);
    EXPECT_FALSE(std::filesystem::exists(svg));
    const std::uint64_t smallest = named_smallest(refused.err);
    ASSERT_GT(smallest, 0u) << refused.err;
    const std::string at_smallest = std::to_string(smallest >> 20) + "M";
    EXPECT_EQ(run_capturing_both({"section", zipper.string(), "--plane", "y=0.1", "--svg", svg, "--memory", at_smallest}).status, kSuccess);
    EXPECT_TRUE(std::filesystem::exists(svg));
    const std::string torus = write_torus_phantom(dir).string();
    const OutAndErr scan = run_capturing_both({"section", torus, "--iso", "0.5", "--error", "0.25", "--plane", "z=32", "--memory", "1M"});
    EXPECT_EQ(scan.status, kUsageError);
    EXPECT_GT(named_smallest(scan.err), 0u) << scan.err;
}

std::string file_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A command that needs the whole grid or mesh: under the estimate, exit 2 naming it, the output
/// not written; at the named limit it runs, writing what it writes without --memory.
void expect_refused_then_run_at_the_estimate(const std::vector<std::string>& args, const std::filesystem::path& output) {
    const OutAndErr refused = run_capturing_both(concat(args, {"--memory", "1M", "-q"}));
    EXPECT_EQ(refused.status, kUsageError) << refused.err;
    EXPECT_NE(refused.err.find("--memory: expected at least"), std::string::npos) << refused.err;
    EXPECT_FALSE(std::filesystem::exists(output));
    const std::uint64_t smallest = named_smallest(refused.err);
    ASSERT_GT(smallest, 0u) << refused.err;
    const OutAndErr bounded = run_capturing_both(concat(args, {"--memory", std::to_string(smallest >> 20) + "M", "-q"}));
    EXPECT_EQ(bounded.status, kSuccess) << bounded.err;
    if (output.empty()) return;
    const std::string bounded_bytes = file_bytes(output);
    EXPECT_FALSE(bounded_bytes.empty());
    const OutAndErr whole = run_capturing_both(concat(args, {"-q"}));  // over it (the outputs are replaced atomically)
    EXPECT_EQ(whole.status, kSuccess) << whole.err;
    EXPECT_TRUE(file_bytes(output) == bounded_bytes) << "--memory changed " << output;
}

TEST(MemoryEstimateTest, ConvertRefusesUnderTheSurveyedGrid) {
    VDBMESH_SHARED_DATA(head, "raw_vtk_headsq/headsq_64x64x93_int16le.raw");
    const test::ScratchDir dir;
    expect_refused_then_run_at_the_estimate(
        {"convert", head.string(), "--raw-dims", "64,64,93", "--raw-type", "i16", "--iso", "1000.5", "-o", (dir / "head.vdb").string()},
        dir / "head.vdb");
}

TEST(MemoryEstimateTest, LatticeAndProcessRefuseUnderTheirLeaves) {
    const test::ScratchDir dir;
    const std::filesystem::path lattice = dir / "gyroid.vdb", grown = dir / "grown.vdb";
    expect_refused_then_run_at_the_estimate(
        {"lattice", "gyroid", "--period", "2", "--thickness", "0.5", "--box", "4", "--voxel", "0.1", "-o", lattice.string()}, lattice);
    expect_refused_then_run_at_the_estimate({"process", lattice.string(), "--deposit", "0.2", "-o", grown.string()}, grown);
}

TEST(MemoryEstimateTest, CompareRefusesUnderTheGridAndItsMeshes) {
    expect_refused_then_run_at_the_estimate(
        {"compare", "--phantom", "sphere", "--size", "32", "--error", "0.25", "--adaptivity", "0.25", "--no-budget", "--samples", "1000"}, {});
}

TEST(MemoryEstimateTest, ReconstructRefusesUnderThePointsAndVoxels) {
    const test::ScratchDir dir;
    // 2000 points on a unit sphere, with their normals (a spiral).
    std::string text;
    for (int i = 0; i < 2000; ++i) {
        const double z = 1 - (2 * i + 1) / 2000.0, r = std::sqrt(1 - z * z), phi = i * 2.399963229728653;
        const double x = r * std::cos(phi), y = r * std::sin(phi);
        text += std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + " " + std::to_string(x) + " " + std::to_string(y) +
                " " + std::to_string(z) + "\n";
    }
    std::ofstream(dir / "sphere.xyz") << text;
    expect_refused_then_run_at_the_estimate({"reconstruct", (dir / "sphere.xyz").string(), "-o", (dir / "sphere.ply").string()},
                                            dir / "sphere.ply");
}

}  // namespace
}  // namespace vdbmesh::cli
