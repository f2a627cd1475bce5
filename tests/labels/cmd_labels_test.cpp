// `vdbmesh info`, `mesh --labels` and `measure --labels` on the AAL atlas, run in-process.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "label_view.h"
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

TEST(LabelCommandsTest, MeasureListsVolumesAgainstVoxels) {
    VDBMESH_SHARED_DATA(aal, "nifti_mricron_label_atlases/aal.nii.gz");
    const Output o = run_capturing({"measure", aal.string(), "--labels", "37", "--json", "-q"});
    ASSERT_EQ(o.status, 0);
    const nlohmann::json j = nlohmann::json::parse(o.out);
    ASSERT_EQ(j["labels"].size(), 1u);
    EXPECT_EQ(j["labels"][0]["name"], "Hippocampus_L");
    EXPECT_EQ(j["labels"][0]["voxels"], 7469);
    // The volume is put back to the voxel count (1 mm voxels): well within the 2%.
    EXPECT_NEAR(j["labels"][0]["volume"].get<double>(), 7469.0, 0.02 * 7469);
    const Output csv = run_capturing({"measure", aal.string(), "--labels", "37", "--csv", "-q"});
    ASSERT_EQ(csv.status, 0);
    EXPECT_EQ(csv.out.rfind("value,name,voxels,voxel_volume,volume,volume_error,area,centroid_x,centroid_y,centroid_z\n37,Hippocampus_L,7469,", 0), 0u)
        << csv.out;
}

TEST(LabelCommandsTest, BadOutputsAndLabelListsAreUsageErrors) {
    VDBMESH_SHARED_DATA(aal, "nifti_mricron_label_atlases/aal.nii.gz");
    ScratchDir dir;
    EXPECT_EQ(run({"mesh", aal.string(), "--labels", "all", "-o", (dir / "one.stl").string(), "-q"}), 2);
    EXPECT_EQ(run({"mesh", aal.string(), "--labels", "2-1", "-o", (dir / "x.ply").string(), "-q"}), 2);
    EXPECT_EQ(run({"mesh", aal.string(), "--labels", "all", "--iso", "3", "-o", (dir / "x.ply").string(), "-q"}), 2);
    EXPECT_EQ(run({"measure", aal.string(), "--csv", "-q"}), 2);
    EXPECT_FALSE(std::filesystem::exists(dir / "one.stl"));
    EXPECT_FALSE(std::filesystem::exists(dir / "x.ply"));
}

TEST(LabelCommandsTest, ViewShowsEachLabelAsARunOfOneMesh) {
    VDBMESH_SHARED_DATA(aal, "nifti_mricron_label_atlases/aal.nii.gz");
    LabelFlags flags;
    flags.labels = "37,38";
    const ViewSource source = label_view_source({aal.string()}, ReadFlags{}, flags);
    ASSERT_EQ(source.labels.size(), 2u);
    EXPECT_EQ(source.labels[0].name, "Hippocampus_L");
    EXPECT_EQ(source.labels[1].value, 38u);
    // The runs follow one another and cover the mesh.
    EXPECT_EQ(source.labels[0].first_triangle, 0u);
    EXPECT_EQ(source.labels[1].first_triangle, source.labels[0].triangles);
    EXPECT_EQ(source.labels[1].first_vertex, source.labels[0].vertices);
    EXPECT_EQ(source.mesh->triangles.size(), source.labels[0].triangles + source.labels[1].triangles);
    EXPECT_EQ(source.mesh->vertices.size(), source.labels[0].vertices + source.labels[1].vertices);
    for (const ViewLabel& label : source.labels)
        for (double c : label.colour) EXPECT_TRUE(c >= 0 && c <= 1);  // AAL's table has no colours: the palette's
    // Each label's mesh is checked alone, so the two hippocampi do not count as one mesh.
    const nlohmann::json figures = nlohmann::json::parse(label_figures(*source.mesh, source.labels));
    EXPECT_EQ(figures["labels"], 2);
    EXPECT_TRUE(figures["closed"].get<bool>());
    EXPECT_EQ(figures["self_intersecting_pairs"], 0);
    EXPECT_EQ(figures["nonmanifold_edges"], 0);
    EXPECT_GT(figures["volume"].get<double>(), 0);
}

TEST(LabelCommandsTest, ViewRefusesAnIsovalueOrNamesWithoutLabels) {
    VDBMESH_SHARED_DATA(aal, "nifti_mricron_label_atlases/aal.nii.gz");
    EXPECT_EQ(run({"view", aal.string(), "--labels", "all", "--iso", "3", "--no-open", "-q"}), 2);
    EXPECT_EQ(run({"view", aal.string(), "--label-names", (aal.parent_path() / "aal.nii.txt").string(), "--no-open", "-q"}), 2);
}

}  // namespace
}  // namespace vdbmesh::cli
