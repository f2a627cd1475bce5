// `vdbmesh info`, `mesh --labels` and `measure --labels` on the AAL atlas, run in-process.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "test_data.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh::cli {
namespace {

using test::ScratchDir;

struct Output {
    int status;
    std::string out;
};

Output run_capturing(const std::vector<std::string>& args) {
    testing::internal::CaptureStdout();
    const int status = run(args);
    return {status, testing::internal::GetCapturedStdout()};
}

std::string read_all(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(LabelCommandsTest, InfoListsTheLabelsWithTheirNames) {
    VDBMESH_SHARED_DATA(aal, "nifti_mricron_label_atlases/aal.nii.gz");
    const Output o = run_capturing({"info", aal.string(), "--json", "-q"});
    ASSERT_EQ(o.status, 0);
    const nlohmann::json j = nlohmann::json::parse(o.out);
    ASSERT_EQ(j["labels"].size(), 117u);  // 116 structures and the background
    EXPECT_EQ(j["labels"][1]["name"], "Precentral_L");
    EXPECT_EQ(j["labels"][1]["voxels"], 28174);
    EXPECT_NE(j["label_table"].get<std::string>().find("aal.nii.txt"), std::string::npos);
}

TEST(LabelCommandsTest, MeshWritesOneNamedFilePerLabel) {
    VDBMESH_SHARED_DATA(aal, "nifti_mricron_label_atlases/aal.nii.gz");
    ScratchDir dir;
    const Output o = run_capturing({"mesh", aal.string(), "--labels", "1,37", "-o", (dir / "out").string() + "/", "--json", "-q"});
    ASSERT_EQ(o.status, 0);
    const nlohmann::json j = nlohmann::json::parse(o.out);
    EXPECT_EQ(j["labels"], nlohmann::json::array({1, 37}));
    EXPECT_FALSE(read_mesh(dir / "out" / "1_Precentral_L.stl").triangles.empty());
    EXPECT_FALSE(read_mesh(dir / "out" / "37_Hippocampus_L.stl").triangles.empty());
}

TEST(LabelCommandsTest, MeshWritesAPlyWithLabelPairsAndANamedGltf) {
    VDBMESH_SHARED_DATA(aal, "nifti_mricron_label_atlases/aal.nii.gz");
    ScratchDir dir;
    ASSERT_EQ(run({"mesh", aal.string(), "--labels", "1-2", "-o", (dir / "walls.ply").string(), "-q"}), 0);
    const std::string ply = read_all(dir / "walls.ply");
    EXPECT_NE(ply.find("property ushort label_inside\nproperty ushort label_outside\n"), std::string::npos);
    ASSERT_EQ(run({"mesh", aal.string(), "--labels", "1-2", "-o", (dir / "labels.gltf").string(), "-q"}), 0);
    const nlohmann::json gltf = nlohmann::json::parse(read_all(dir / "labels.gltf"));
    ASSERT_EQ(gltf["meshes"].size(), 2u);
    EXPECT_EQ(gltf["meshes"][0]["name"], "Precentral_L");
    EXPECT_EQ(gltf["nodes"][1]["extras"]["label"], 2);
}

TEST(LabelCommandsTest, BadOutputsAndLabelListsAreUsageErrors) {
    VDBMESH_SHARED_DATA(aal, "nifti_mricron_label_atlases/aal.nii.gz");
    ScratchDir dir;
    EXPECT_EQ(run({"mesh", aal.string(), "--labels", "all", "-o", (dir / "one.stl").string(), "-q"}), 2);
    EXPECT_EQ(run({"mesh", aal.string(), "--labels", "2-1", "-o", (dir / "x.ply").string(), "-q"}), 2);
    EXPECT_FALSE(std::filesystem::exists(dir / "one.stl"));
    EXPECT_FALSE(std::filesystem::exists(dir / "x.ply"));
}

}  // namespace
}  // namespace vdbmesh::cli
