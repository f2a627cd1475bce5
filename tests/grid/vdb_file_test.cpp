#include <gtest/gtest.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "grid_test_util.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"

namespace vdbmesh {
namespace {

using test::ScratchDir;

openvdb::FloatGrid::Ptr small_converted_grid(const ScratchDir& dir) {
    const auto volume = test::make_volume({20, 18, 16}, [](int x, int y, int z) {
        return static_cast<float>(6 - std::sqrt((x - 9.0) * (x - 9.0) + (y - 8.0) * (y - 8.0) + (z - 7.0) * (z - 7.0)));
    });
    auto reader = test::write_and_open(volume, dir / "ball.raw");
    ConvertOptions options;
    options.iso = 0.5;
    return convert_to_grid(*reader, options);
}

bool tool_available(const char* name) {
    return std::system((std::string("command -v ") + name + " > /dev/null 2>&1").c_str()) == 0;
}

/// Skips (or fails under VDBMESH_REQUIRE_DATA=1) when an OpenVDB command-line tool is missing.
#define REQUIRE_TOOL(name)                                                                   \
    if (!tool_available(name)) {                                                             \
        if (test::data_required()) FAIL() << name << " missing (VDBMESH_REQUIRE_DATA=1)";   \
        GTEST_SKIP() << name << " missing (package libopenvdb-tools)";                       \
    }

void write_with_openvdb(const openvdb::GridCPtrVec& grids, const std::filesystem::path& path) {
    openvdb::initialize();
    openvdb::io::File file(path.string());
    file.write(grids);
    file.close();
}

TEST(VdbFileTest, RoundTripKeepsValuesTransformAndMetadata) {
    ScratchDir dir;
    const auto grid = small_converted_grid(dir);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
    write_vdb(*grid, dir / "out.vdb");
    const auto back = read_vdb(dir / "out.vdb");
    EXPECT_EQ(back->getName(), "density");
    EXPECT_EQ(back->activeVoxelCount(), grid->activeVoxelCount());
    EXPECT_EQ(back->tree().leafCount(), grid->tree().leafCount());
    EXPECT_EQ(back->background(), grid->background());
    EXPECT_EQ(back->voxelSize(), grid->voxelSize());
    EXPECT_EQ(stored_isovalue(*back), 0.5);
    EXPECT_EQ(back->metaValue<openvdb::Vec3i>(kMetaScanMax), openvdb::Vec3i(19, 17, 15));
    auto accessor = back->getConstAccessor();
    for (auto it = grid->tree().cbeginValueAll(); it; ++it)
        if (it.isVoxelValue()) ASSERT_EQ(accessor.getValue(it.getCoord()), *it) << it.getCoord();
}

std::string file_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// OpenVDB writes a random file id into every archive header; ours is made from the grid, so
// the same grid gives the same bytes, and the file still opens in OpenVDB's own reader.
TEST(VdbFileTest, TheSameGridGivesTheSameBytes) {
    ScratchDir dir;
    const auto grid = small_converted_grid(dir);
    write_vdb(*grid, dir / "first.vdb");
    write_vdb(*grid, dir / "second.vdb");
    const std::string first = file_bytes(dir / "first.vdb");
    ASSERT_GT(first.size(), 100u);
    EXPECT_EQ(first, file_bytes(dir / "second.vdb"));
    openvdb::io::File file((dir / "first.vdb").string());
    ASSERT_NO_THROW(file.open());
    EXPECT_EQ(file.getUniqueTag().size(), 36u);
    EXPECT_EQ(first.substr(21, 36), file.getUniqueTag());  // the id sits where we wrote it
    EXPECT_EQ(openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"))->activeVoxelCount(), grid->activeVoxelCount());
    file.close();
    // A different grid gets a different id.
    grid->tree().setValue(openvdb::Coord(1, 1, 1), 3.0f);
    write_vdb(*grid, dir / "third.vdb");
    EXPECT_NE(file_bytes(dir / "third.vdb").substr(21, 36), first.substr(21, 36));
}

TEST(VdbFileTest, FailedWriteLeavesNothingBehind) {
    ScratchDir dir;
    const auto grid = small_converted_grid(dir);
    EXPECT_THROW(write_vdb(*grid, dir / "missing" / "out.vdb"), Error);
    std::filesystem::create_directory(dir / "taken.vdb");  // the rename onto a folder fails
    EXPECT_THROW(write_vdb(*grid, dir / "taken.vdb"), Error);
    for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
        EXPECT_TRUE(entry.path().filename() == "ball.raw" || entry.path().filename() == "taken.vdb") << entry.path();
}

TEST(VdbFileTest, ReadingBadFilesIsFormatError) {
    ScratchDir dir;
    EXPECT_THROW(read_vdb(dir / "absent.vdb"), FormatError);
    std::ofstream(dir / "junk.vdb") << "this is not a vdb file, just text long enough to hold a header";
    EXPECT_THROW(read_vdb(dir / "junk.vdb"), FormatError);
    EXPECT_THROW(describe_vdb_file(dir / "junk.vdb"), FormatError);
    // A valid file whose grids are all vectors.
    auto vectors = openvdb::Vec3SGrid::create();
    vectors->setName("velocity");
    vectors->tree().setValue(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1, 0, 0));
    write_with_openvdb({vectors}, dir / "vectors.vdb");
    try {
        read_vdb(dir / "vectors.vdb");
        FAIL() << "expected FormatError";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("velocity"), std::string::npos) << e.what();
    }
    // A truncated copy of a good file.
    const auto grid = small_converted_grid(dir);
    write_vdb(*grid, dir / "good.vdb");
    std::filesystem::copy_file(dir / "good.vdb", dir / "cut.vdb");
    std::filesystem::resize_file(dir / "cut.vdb", std::filesystem::file_size(dir / "good.vdb") / 2);
    EXPECT_THROW(read_vdb(dir / "cut.vdb"), FormatError);
}

TEST(VdbFileTest, ReadsAnOpenVdbLevelSetSphere) {
    ScratchDir dir;
    openvdb::initialize();
    auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(10.0f, openvdb::Vec3f(0), 0.5f);
    sphere->setName("sphere");
    write_with_openvdb({sphere}, dir / "sphere.vdb");
    const auto back = read_vdb(dir / "sphere.vdb");
    EXPECT_EQ(back->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_EQ(back->activeVoxelCount(), sphere->activeVoxelCount());
    EXPECT_FALSE(stored_isovalue(*back));
}

TEST(VdbFileTest, ReadsWhatVdbToolWrites) {
    REQUIRE_TOOL("vdb_tool");
    ScratchDir dir;
    const std::string command = "vdb_tool -sphere dim=48 radius=1 -write '" + (dir / "tool.vdb").string() +
                                "' > /dev/null 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    const auto grid = read_vdb(dir / "tool.vdb");
    EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_GT(grid->activeVoxelCount(), 1000u);
}

TEST(VdbFileTest, VdbToolReadsWhatWeWrite) {
    REQUIRE_TOOL("vdb_tool");
    ScratchDir dir;
    const auto grid = small_converted_grid(dir);
    write_vdb(*grid, dir / "out.vdb");
    const std::string command = "vdb_tool -read '" + (dir / "out.vdb").string() + "' -print > '" +
                                (dir / "print.txt").string() + "' 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream in(dir / "print.txt");
    const std::string printed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(printed.find("voxels = " + std::to_string(grid->activeVoxelCount())), std::string::npos) << printed;
}

TEST(VdbFileTest, VdbPrintReadsWhatWeWrite) {
    REQUIRE_TOOL("vdb_print");
    ScratchDir dir;
    write_vdb(*small_converted_grid(dir), dir / "out.vdb");
    const std::string command =
        "vdb_print -l '" + (dir / "out.vdb").string() + "' > '" + (dir / "print.txt").string() + "' 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream in(dir / "print.txt");
    const std::string printed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(printed.find("density"), std::string::npos) << printed;
    EXPECT_NE(printed.find(kMetaIsovalue), std::string::npos) << printed;
}

TEST(GridInfoTest, DescribesCountsBoxesAndMetadata) {
    ScratchDir dir;
    const auto grid = small_converted_grid(dir);
    const GridInfo info = describe_grid(*grid);
    EXPECT_EQ(info.name, "density");
    EXPECT_EQ(info.value_type, "float");
    EXPECT_EQ(info.active_voxels, grid->activeVoxelCount());
    EXPECT_EQ(info.leaf_nodes, grid->tree().leafCount());
    EXPECT_GT(info.memory_bytes, info.leaf_nodes * 512 * sizeof(float));
    EXPECT_EQ(info.index_bbox, grid->evalActiveVoxelBoundingBox());
    ASSERT_TRUE(info.value_range);
    EXPECT_LE(info.value_range->first, 0.5);
    EXPECT_GT(info.value_range->second, 0.5);
    bool has_iso = false;
    for (const auto& [name, value] : info.metadata) has_iso = has_iso || (name == kMetaIsovalue && value == "0.5");
    EXPECT_TRUE(has_iso);
}

TEST(GridInfoTest, DescribesEveryGridOfAFile) {
    ScratchDir dir;
    auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(5.0f, openvdb::Vec3f(0), 1.0f);
    sphere->setName("sphere");
    auto vectors = openvdb::Vec3SGrid::create();
    vectors->setName("velocity");
    write_with_openvdb({sphere, vectors}, dir / "two.vdb");
    const auto infos = describe_vdb_file(dir / "two.vdb");
    ASSERT_EQ(infos.size(), 2u);
    EXPECT_EQ(infos[0].name, "sphere");
    EXPECT_EQ(infos[0].grid_class, "level set");
    EXPECT_EQ(infos[0].active_voxels, sphere->activeVoxelCount());
    EXPECT_EQ(infos[1].value_type, "vec3s");
    EXPECT_TRUE(infos[1].index_bbox.empty());
    EXPECT_FALSE(infos[1].value_range);
}

}  // namespace
}  // namespace vdbmesh
