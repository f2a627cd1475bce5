// `vdbmesh lattice` and `vdbmesh info --shared` run in-process: the figures of --measure against
// the plain references on the expanded grid, the outputs (.vdb, mesh judged by CGAL, glTF),
// bad input, and the gyroid clipped to the bunny CT's solid (shared data).

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cgal_judge.h"
#include "cli.h"
#include "test_data.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/lattice.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/shared_process.h"
#include "vdbmesh/shared_tree.h"

namespace vdbmesh::test {
namespace {

std::vector<std::string> gyroid_args() {
    return {"lattice", "gyroid", "--period", "2", "--thickness", "0.5", "--box", "6,5,4", "--voxel", "0.125", "--quiet"};
}

nlohmann::json run_json(std::vector<std::string> args, int expected = 0) {
    args.push_back("--json");
    testing::internal::CaptureStdout();
    const int status = cli::run(args);
    const std::string out = testing::internal::GetCapturedStdout();
    EXPECT_EQ(status, expected) << out;
    return status == 0 ? nlohmann::json::parse(out) : nlohmann::json();
}

TEST(LatticeCli, MeasureMatchesPlainFiguresOfTheWrittenGrid) {
    const ScratchDir scratch;
    auto args = gyroid_args();
    args.push_back("--measure");
    const nlohmann::json m = run_json(args);
    for (const char* key : {"volume", "area", "components", "voxels", "unique_leaves", "leaves"}) ASSERT_TRUE(m.contains(key)) << key;
    EXPECT_LT(m["unique_leaves"].get<double>() * 2, m["leaves"].get<double>());
    // The same lattice written as .vdb, measured plainly.
    args = gyroid_args();
    args.insert(args.end(), {"-o", (scratch / "g.vdb").string()});
    ASSERT_EQ(cli::run(args), 0);
    const openvdb::FloatGrid::Ptr grid = read_vdb(scratch / "g.vdb");
    EXPECT_EQ(grid->tree().leafCount(), m["leaves"].get<std::uint64_t>());
    EXPECT_EQ(plain_active_voxels(*grid), m["voxels"].get<std::uint64_t>());
    EXPECT_NEAR(plain_volume(*grid), m["volume"].get<double>(), 1e-9 * m["volume"].get<double>());
    EXPECT_EQ(plain_components(*grid), m["components"].get<std::uint64_t>());
    MeshOptions mc;
    mc.method = MeshMethod::mc;
    mc.inside = Inside::below;
    const Mesh plain = mesh_grid(*grid, mc).mesh;
    EXPECT_NEAR(mesh_integrals(plain).area, m["area"].get<double>(), 1e-5 * m["area"].get<double>());
    // info --shared reads it back as the same shared tree.
    const nlohmann::json info = run_json({"info", (scratch / "g.vdb").string(), "--shared"});
    EXPECT_EQ(info["shared"]["leaves"]["stored"], m["unique_leaves"]);
    EXPECT_EQ(info["shared"]["leaves"]["represented"], m["leaves"]);
}

TEST(LatticeCli, MeshOutputIsCleanForEveryKind) {
    const ScratchDir scratch;
    for (const char* kind : {"gyroid", "schwarz-p", "diamond", "bcc"}) {
        std::vector<std::string> args = {"lattice", kind, "--period", "2", "--box", "4", "--voxel", "0.125", "--quiet"};
        if (std::string(kind) == "schwarz-p") args.insert(args.end(), {"--level", "0.2"});
        else args.insert(args.end(), {"--thickness", "0.4"});
        args.insert(args.end(), {"-o", (scratch / "m.ply").string()});
        ASSERT_EQ(cli::run(args), 0) << kind;
        const Mesh mesh = read_mesh(scratch / "m.ply");
        ASSERT_FALSE(mesh.triangles.empty()) << kind;
        const CgalVerdict verdict = judge_with_cgal(mesh);
        EXPECT_TRUE(verdict.clean()) << kind << ": " << verdict.describe();
    }
}

TEST(LatticeCli, InstancedGltfPlacesEveryBlock) {
    const ScratchDir scratch;
    auto args = gyroid_args();
    args.insert(args.end(), {"-o", (scratch / "g.gltf").string()});
    const nlohmann::json figures = run_json(args);
    std::ifstream in(scratch / "g.gltf");
    const nlohmann::json gltf = nlohmann::json::parse(in);
    EXPECT_EQ(gltf["asset"]["version"], "2.0");
    EXPECT_EQ(gltf["extensionsUsed"][0], "EXT_mesh_gpu_instancing");
    std::uint64_t instances = 0;
    for (const auto& node : gltf["nodes"]) {
        const int accessor = node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"];
        instances += gltf["accessors"][accessor]["count"].get<std::uint64_t>();
    }
    EXPECT_EQ(instances, figures["instances"].get<std::uint64_t>());
    EXPECT_EQ(gltf["meshes"].size(), figures["parts"].get<std::size_t>());
    // The binary form starts with the glTF magic.
    args = gyroid_args();
    args.insert(args.end(), {"-o", (scratch / "g.glb").string()});
    ASSERT_EQ(cli::run(args), 0);
    std::ifstream glb(scratch / "g.glb", std::ios::binary);
    char magic[4];
    glb.read(magic, 4);
    EXPECT_EQ(std::string(magic, 4), "glTF");
}

TEST(LatticeCli, BadInputWritesNothing) {
    const ScratchDir scratch;
    const std::string out = (scratch / "x.vdb").string();
    auto with = [&](std::vector<std::string> extra) {
        auto args = gyroid_args();
        args.insert(args.end(), extra.begin(), extra.end());
        return cli::run(args);
    };
    EXPECT_EQ(with({}), cli::kUsageError);                              // neither -o nor --measure
    EXPECT_EQ(with({"-o", (scratch / "x.txt").string()}), cli::kUsageError);
    EXPECT_EQ(with({"--measure", "-o", out}), cli::kUsageError);
    EXPECT_EQ(cli::run({"lattice", "kelvin", "--period", "1", "--thickness", "0.1", "--box", "1", "--voxel", "0.1", "-o", out}),
              cli::kUsageError);
    EXPECT_EQ(cli::run({"lattice", "gyroid", "--period", "1", "--thickness", "0.1", "--box", "1,2", "--voxel", "0.1", "-o", out}),
              cli::kUsageError);
    EXPECT_NE(with({"--clip", (scratch / "missing.stl").string(), "-o", out}), 0);
    EXPECT_EQ(cli::run({"info", out, "--shared"}), cli::kRuntimeError);
    EXPECT_FALSE(std::filesystem::exists(out));
    EXPECT_TRUE(std::filesystem::is_empty(scratch.path()));
}

TEST(ProcessCli, StepsRunInTheOrderGiven) {
    const ScratchDir scratch;
    const std::string in = (scratch / "in.vdb").string(), stop = (scratch / "stop.vdb").string();
    ASSERT_EQ(cli::run({"lattice", "gyroid", "--period", "2", "--thickness", "0.5", "--box", "3", "--voxel", "0.125", "-o", in, "--quiet"}), 0);
    ASSERT_EQ(cli::run({"lattice", "schwarz-p", "--period", "2", "--level", "0", "--box", "3", "--voxel", "0.125", "-o", stop, "--quiet"}), 0);
    const auto grid = read_vdb(in);
    const auto stop_grid = read_vdb(stop);
    const std::string a = (scratch / "a.vdb").string(), b = (scratch / "b.vdb").string();
    ASSERT_EQ(cli::run({"process", in, "--deposit", "0.25", "--etch", "z:0.5", "--stop-layer", stop, "-o", a, "--quiet"}), 0);
    ASSERT_EQ(cli::run({"process", in, "--etch", "z:0.5", "--deposit", "0.25", "--stop-layer", stop, "-o", b, "--quiet"}), 0);
    const SharedTree tree = build_shared_tree(*grid);
    const auto expected_a = to_float_grid(shared_etch(shared_deposit(tree, 0.25), 2, 1, 0.5, stop_grid.get()));
    const auto expected_b = to_float_grid(shared_deposit(shared_etch(tree, 2, 1, 0.5, stop_grid.get()), 0.25));
    EXPECT_EQ(read_vdb(a)->activeVoxelCount(), expected_a->activeVoxelCount());
    EXPECT_EQ(read_vdb(b)->activeVoxelCount(), expected_b->activeVoxelCount());
    EXPECT_NE(expected_a->activeVoxelCount(), expected_b->activeVoxelCount());
    // Bad input: nothing written.
    const std::string c = (scratch / "c.vdb").string();
    EXPECT_EQ(cli::run({"process", in, "--etch", "w:1", "-o", c}), cli::kUsageError);
    EXPECT_EQ(cli::run({"process", in, "--deposit", "-1", "-o", c}), cli::kUsageError);
    EXPECT_EQ(cli::run({"process", in, "-o", c}), cli::kUsageError);
    EXPECT_EQ(cli::run({"process", in, "--deposit", "1", "-o", (scratch / "c.stl").string()}), cli::kUsageError);
    EXPECT_FALSE(std::filesystem::exists(c));
}

TEST(LatticeCli, GyroidClippedToTheBunnyIsCleanForCgal) {
    VDBMESH_SHARED_DATA(part1, "raw_stanford_ct_bunny/bunny_ct_512x512x361_uint16be.part1of2.raw.gz");
    VDBMESH_SHARED_DATA(part2, "raw_stanford_ct_bunny/bunny_ct_512x512x361_uint16be.part2of2.raw.gz");
    const ScratchDir scratch;
    const std::string out = (scratch / "implant.stl").string();
    const nlohmann::json figures = run_json({"lattice", "gyroid", "--period", "30", "--thickness", "6", "--voxel", "2", "--clip",
                                             part1.string(), part2.string(), "--raw-dims", "512,512,361", "--raw-type", "i16",
                                             "--raw-endian", "big", "--clip-iso", "1200.5", "-o", out, "--quiet"});
    const Mesh mesh = read_mesh(out);
    ASSERT_GT(mesh.triangles.size(), 1000u);
    const CgalVerdict verdict = judge_with_cgal(mesh);
    std::cout << "[ figures  ] gyroid clipped to the bunny CT: " << mesh.triangles.size() << " triangles, CGAL: " << verdict.describe()
              << "\n";
    EXPECT_TRUE(verdict.clean()) << verdict.describe();
}

}  // namespace
}  // namespace vdbmesh::test
