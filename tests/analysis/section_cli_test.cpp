// `vdbmesh section` run in-process: a scan's section by one plane and by a range of planes,
// as JSON and SVG; bad plane specifications; no output file when the command fails.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include "cli.h"
#include "run_json.h"
#include "test_data.h"
#include "test_meshes.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh::test {
namespace {

std::string read_text(const std::filesystem::path& path) {
    std::ostringstream text;
    text << std::ifstream(path).rdbuf();
    return text.str();
}

TEST(SectionCliTest, SpherePhantomScanSectionsAsJsonAndSvg) {
    const ScratchDir scratch;
    const auto scan = scratch / "sphere.nii";
    ASSERT_EQ(cli::run({"phantom", "sphere", "--size", "64", "-o", scan.string(), "--quiet"}), cli::kSuccess);
    const auto svg = scratch / "cut.svg";
    int status = 0;
    const nlohmann::json j = run_json({"section", scan.string(), "--iso", "0.5", "--plane", "z=31.5", "--planes",
                                       "x=11.5:51.5:10", "--svg", svg.string(), "--json"}, status);
    ASSERT_EQ(status, cli::kSuccess);
    ASSERT_EQ(j["sections"].size(), 1u + 5u);
    const auto& mid = j["sections"][0];
    EXPECT_EQ(mid["label"], "z=31.5");
    EXPECT_EQ(mid["loops"], 1);
    EXPECT_EQ(mid["holes"], 0);
    const double disc = M_PI * 20 * 20;  // the preset's radius, 40 at 128^3, scaled to 64^3
    EXPECT_NEAR(mid["area"].get<double>(), disc, 0.01 * disc);  // 1%: half the resolution of the 0.5% figure
    EXPECT_NEAR(mid["centroid"][2].get<double>(), 31.5, 1e-9);
    EXPECT_EQ(j["sections"][1]["label"], "x=11.5");
    EXPECT_EQ(j["sections"][5]["label"], "x=51.5");
    EXPECT_EQ(j["sections"][1]["loops"], 0);  // 11.5 lies outside the ball (radius 20 about 31.5)
    const std::string picture = read_text(svg);
    EXPECT_NE(picture.find("<svg"), std::string::npos);
    EXPECT_NE(picture.find("z=31.5"), std::string::npos);
}

TEST(SectionCliTest, GeneralPlaneOnAMeshFile) {
    const ScratchDir scratch;
    write_mesh(cube({0, 0, 0}, 2), scratch / "cube.ply");
    int status = 0;
    const nlohmann::json j =
        run_json({"section", (scratch / "cube.ply").string(), "--normal", "0,0,2", "--offset", "1", "--json"}, status);
    ASSERT_EQ(status, cli::kSuccess);
    EXPECT_DOUBLE_EQ(j["sections"][0]["area"].get<double>(), 4);
    EXPECT_DOUBLE_EQ(j["sections"][0]["perimeter"].get<double>(), 8);
    EXPECT_EQ(cli::run({"section", (scratch / "cube.ply").string(), "--plane", "y=1"}), cli::kSuccess);  // text
}

TEST(SectionCliTest, BadPlanesAreUsageErrorsAndWriteNothing) {
    const ScratchDir scratch;
    write_mesh(cube(), scratch / "cube.stl");
    const std::string mesh = (scratch / "cube.stl").string(), svg = (scratch / "cut.svg").string();
    for (const std::vector<std::string>& flags :
         {std::vector<std::string>{}, {"--plane", "w=1"}, {"--plane", "z="}, {"--plane", "z=1,2"}, {"--planes", "z=5:1:1"},
          {"--planes", "z=0:1:0"}, {"--normal", "0,0,0"}, {"--normal", "1,2"}}) {
        std::vector<std::string> args{"section", mesh, "--svg", svg};
        args.insert(args.end(), flags.begin(), flags.end());
        EXPECT_EQ(cli::run(args), cli::kUsageError) << testing::PrintToString(flags);
        EXPECT_FALSE(std::filesystem::exists(svg));
    }
}

TEST(SectionCliTest, OpenMeshIsARuntimeError) {
    const ScratchDir scratch;
    Mesh open = cube();
    open.triangles.pop_back();
    write_mesh(open, scratch / "open.stl");
    EXPECT_EQ(cli::run({"section", (scratch / "open.stl").string(), "--plane", "z=0.5"}), cli::kRuntimeError);
}

}  // namespace
}  // namespace vdbmesh::test
