// `vdbmesh info` and `vdbmesh convert`, run in-process.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "concat_args.h"
#include "test_data.h"
#include "vdbmesh/grid.h"

namespace vdbmesh::cli {
namespace {

using test::ScratchDir;

/// A 16 x 12 x 10 u8 raw volume: 10 everywhere, 200 in the box [4, 11] x [3, 8] x [2, 7].
std::vector<unsigned char> box_volume() {
    std::vector<unsigned char> bytes;
    for (int z = 0; z < 10; ++z)
        for (int y = 0; y < 12; ++y)
            for (int x = 0; x < 16; ++x)
                bytes.push_back(x >= 4 && x <= 11 && y >= 3 && y <= 8 && z >= 2 && z <= 7 ? 200 : 10);
    return bytes;
}

std::filesystem::path write_bytes(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    return path;
}

struct Output {
    int status;
    std::string out;
};

Output run_capturing(const std::vector<std::string>& args) {
    testing::internal::CaptureStdout();
    const int status = run(args);
    return {status, testing::internal::GetCapturedStdout()};
}

/// Exactly one JSON object (parse() rejects anything after it but whitespace).
nlohmann::json parse_one_object(const std::string& text) {
    const nlohmann::json j = nlohmann::json::parse(text);
    EXPECT_TRUE(j.is_object());
    return j;
}

std::vector<std::string> raw_flags() { return {"--raw-dims", "16,12,10", "--raw-type", "u8", "-q"}; }

TEST(InfoCommandTest, JsonDescribesARawScan) {
    ScratchDir dir;
    const auto path = write_bytes(dir / "box.raw", box_volume());
    const Output result = run_capturing(concat({"info", path.string(), "--json", "--spacing", "0.5,0.5,2"}, raw_flags()));
    ASSERT_EQ(result.status, kSuccess);
    const auto j = parse_one_object(result.out);
    EXPECT_EQ(j["format"], "raw");
    EXPECT_EQ(j["dims"], nlohmann::json({16, 12, 10}));
    EXPECT_EQ(j["type"], "u8");
    EXPECT_EQ(j["spacing"], nlohmann::json({0.5, 0.5, 2.0}));
    EXPECT_EQ(j["min"], 10.0);
    EXPECT_EQ(j["max"], 200.0);
    EXPECT_EQ(j["percentiles"]["p50"], 10.0);
    EXPECT_EQ(j["percentiles"]["p99"], 200.0);
    EXPECT_EQ(j["suggested_iso"], 104.5);  // Otsu: the middle of the empty gap between 10 and 200
    EXPECT_NE(j["suggested_iso_reason"].get<std::string>().find("Otsu"), std::string::npos);
}

TEST(InfoCommandTest, TextNamesTheSuggestedIsovalue) {
    ScratchDir dir;
    const auto path = write_bytes(dir / "box.raw", box_volume());
    const Output result = run_capturing(concat({"info", path.string()}, raw_flags()));
    ASSERT_EQ(result.status, kSuccess);
    EXPECT_NE(result.out.find("suggested iso   104.5"), std::string::npos) << result.out;
    EXPECT_NE(result.out.find("16 x 12 x 10"), std::string::npos) << result.out;
}

// A header's data file is named by info; one outside the header's folder is read only with
// --allow-outside-data (issue 10, point 5).
TEST(InfoCommandTest, NamesTheDataFileAndRefusesOneOutsideTheHeadersFolder) {
    ScratchDir dir;
    std::filesystem::create_directory(dir / "scan");
    write_bytes(dir / "box.raw", box_volume());
    std::ofstream(dir / "scan" / "box.mhd") << "ObjectType = Image\nNDims = 3\nDimSize = 16 12 10\nElementType = MET_UCHAR\n"
                                                "ElementDataFile = ../box.raw\n";
    const std::string header = (dir / "scan" / "box.mhd").string();
    testing::internal::CaptureStderr();
    EXPECT_EQ(run({"info", header, "-q"}), kRuntimeError);
    const std::string refused = testing::internal::GetCapturedStderr();
    EXPECT_NE(refused.find("ElementDataFile"), std::string::npos) << refused;
    EXPECT_NE(refused.find("--allow-outside-data"), std::string::npos) << refused;
    const Output allowed = run_capturing({"info", header, "--allow-outside-data", "--json", "-q"});
    ASSERT_EQ(allowed.status, kSuccess);
    const auto j = parse_one_object(allowed.out);
    ASSERT_EQ(j["data_files"].size(), 1u);
    EXPECT_NE(j["data_files"][0].get<std::string>().find("box.raw"), std::string::npos);
    const Output text = run_capturing({"info", header, "--allow-outside-data", "-q"});
    EXPECT_NE(text.out.find("data file       "), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("box.raw"), std::string::npos) << text.out;
}

TEST(InfoCommandTest, MissingFileIsRuntimeError) {
    ScratchDir dir;
    EXPECT_EQ(run({"info", (dir / "absent.nii").string()}), kRuntimeError);
    EXPECT_EQ(run({"info", (dir / "absent.vdb").string()}), kRuntimeError);
}

TEST(ConvertCommandTest, ConvertsAndInfoDescribesTheVdb) {
    ScratchDir dir;
    const auto path = write_bytes(dir / "box.raw", box_volume());
    const auto vdb = dir / "box.vdb";
    ASSERT_EQ(run(concat({"convert", path.string(), "--iso", "100", "-o", vdb.string()}, raw_flags())), kSuccess);
    const auto grid = read_vdb(vdb);
    EXPECT_EQ(stored_isovalue(*grid), 100.0);
    EXPECT_TRUE(grid->tree().isValueOn(openvdb::Coord(4, 3, 2)));  // a box corner

    const Output result = run_capturing({"info", vdb.string(), "--json"});
    ASSERT_EQ(result.status, kSuccess);
    const auto j = parse_one_object(result.out);
    EXPECT_EQ(j["format"], "vdb");
    EXPECT_EQ(j["type"], "float");
    EXPECT_EQ(j["suggested_iso"], 100.0);
    EXPECT_EQ(j["active_voxels"], grid->activeVoxelCount());
    EXPECT_EQ(j["min"], 10.0);
    EXPECT_EQ(j["max"], 200.0);
    EXPECT_EQ(j["dims"].size(), 3u);
    EXPECT_EQ(j["spacing"], nlohmann::json({1.0, 1.0, 1.0}));
    EXPECT_EQ(j["grids"][0]["metadata"][kMetaIsovalue], "100");

    const Output text = run_capturing({"info", vdb.string()});
    EXPECT_EQ(text.status, kSuccess);
    EXPECT_NE(text.out.find("grid \"density\""), std::string::npos) << text.out;
}

TEST(ConvertCommandTest, IsoAutoUsesOtsusThreshold) {
    ScratchDir dir;
    const auto path = write_bytes(dir / "box.raw", box_volume());
    ASSERT_EQ(run(concat({"convert", path.string(), "--iso", "auto", "-o", (dir / "a.vdb").string()}, raw_flags())),
              kSuccess);
    EXPECT_EQ(stored_isovalue(*read_vdb(dir / "a.vdb")), 104.5);
}

TEST(ConvertCommandTest, SplitPartsGiveTheSameGrid) {
    ScratchDir dir;
    const auto bytes = box_volume();
    const auto whole = write_bytes(dir / "whole.raw", bytes);
    const auto part1 = write_bytes(dir / "p1.raw", {bytes.begin(), bytes.begin() + 16 * 12 * 4});
    const auto part2 = write_bytes(dir / "p2.raw", {bytes.begin() + 16 * 12 * 4, bytes.end()});
    ASSERT_EQ(run(concat({"convert", whole.string(), "--iso", "50", "-o", (dir / "w.vdb").string()}, raw_flags())), kSuccess);
    ASSERT_EQ(run(concat({"convert", part1.string(), part2.string(), "--iso", "50", "-o", (dir / "s.vdb").string()},
                         raw_flags())),
              kSuccess);
    EXPECT_EQ(read_vdb(dir / "w.vdb")->activeVoxelCount(), read_vdb(dir / "s.vdb")->activeVoxelCount());
}

TEST(ConvertCommandTest, IsoRangeAndBand) {
    ScratchDir dir;
    const auto path = write_bytes(dir / "box.raw", box_volume());
    ASSERT_EQ(run(concat({"convert", path.string(), "--iso-range", "50,150", "--band", "2", "-o", (dir / "r.vdb").string()},
                         raw_flags())),
              kSuccess);
    const auto grid = read_vdb(dir / "r.vdb");
    EXPECT_EQ(grid->metaValue<openvdb::Vec2d>(kMetaIsoRange), openvdb::Vec2d(50, 150));
}

TEST(ConvertCommandTest, UsageErrorsWriteNothing) {
    ScratchDir dir;
    const auto path = write_bytes(dir / "box.raw", box_volume());
    const std::string out = (dir / "out.vdb").string();
    EXPECT_EQ(run(concat({"convert", path.string(), "-o", out}, raw_flags())), kUsageError);  // no isovalue
    EXPECT_EQ(run(concat({"convert", path.string(), "--iso", "1", "--iso-range", "1,2", "-o", out}, raw_flags())),
              kUsageError);
    EXPECT_EQ(run(concat({"convert", path.string(), "--iso", "x", "-o", out}, raw_flags())), kUsageError);
    EXPECT_EQ(run(concat({"convert", path.string(), "--iso-range", "5,1", "-o", out}, raw_flags())), kUsageError);
    EXPECT_EQ(run(concat({"convert", path.string(), "--iso", "1", "--band", "0", "-o", out}, raw_flags())), kUsageError);
    EXPECT_EQ(run(concat({"convert", path.string(), "--iso", "1", "-o", (dir / "out.stl").string()}, raw_flags())),
              kUsageError);
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(ConvertCommandTest, BadInputIsRuntimeErrorAndLeavesNoFile) {
    ScratchDir dir;
    auto bytes = box_volume();
    bytes.resize(bytes.size() - 7);  // truncated
    const auto path = write_bytes(dir / "cut.raw", bytes);
    EXPECT_EQ(run(concat({"convert", path.string(), "--iso", "100", "-o", (dir / "cut.vdb").string()}, raw_flags())),
              kRuntimeError);
    EXPECT_EQ(run({"convert", (dir / "absent.nii").string(), "--iso", "1", "-o", (dir / "x.vdb").string(), "-q"}),
              kRuntimeError);
    EXPECT_EQ(run(concat({"convert", path.string(), "--iso", "1", "-o", (dir / "no" / "x.vdb").string()}, raw_flags())),
              kRuntimeError);
    for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
        EXPECT_EQ(entry.path().filename(), "cut.raw") << "left behind: " << entry.path();
}

TEST(ConvertCommandTest, RealHeadScan) {
    VDBMESH_SHARED_DATA(head, "raw_vtk_headsq/headsq_64x64x93_int16le.raw");
    ScratchDir dir;
    const std::vector<std::string> flags = {"--raw-dims", "64,64,93", "--raw-type", "i16", "--spacing", "3.2,3.2,1.5", "-q"};
    const Output info = run_capturing(concat({"info", head.string(), "--json"}, flags));
    ASSERT_EQ(info.status, kSuccess);
    const auto j = parse_one_object(info.out);
    EXPECT_EQ(j["dims"], nlohmann::json({64, 64, 93}));
    const double iso = j["suggested_iso"];
    EXPECT_GT(iso, j["min"].get<double>());
    EXPECT_LT(iso, j["max"].get<double>());
    const auto vdb = dir / "head.vdb";
    ASSERT_EQ(run(concat({"convert", head.string(), "--iso", "auto", "-o", vdb.string()}, flags)), kSuccess);
    const auto grid = read_vdb(vdb);
    EXPECT_EQ(stored_isovalue(*grid), iso);
    EXPECT_GT(grid->activeVoxelCount(), 1000u);
    EXPECT_DOUBLE_EQ(grid->voxelSize().x(), 3.2);
    EXPECT_DOUBLE_EQ(grid->voxelSize().z(), 1.5);
}

}  // namespace
}  // namespace vdbmesh::cli
