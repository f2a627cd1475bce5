// SplatGridId: what tells whether a splat file belongs to a .vdb, read from the file's header
// and topology alone; the same for the same file, different for another grid or a change.

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include "phantom_grid.h"
#include "test_data.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/splats.h"

namespace vdbmesh {
namespace {

openvdb::FloatGrid::Ptr sphere(int size) { return test::phantom_scan_grid(phantom_preset("sphere", {size, size, size})); }

SplatGridId id_of(const std::filesystem::path& vdb) { return splat_grid_id(vdb, *open_vdb_regions(vdb)); }

TEST(SplatGridId, TheSameFileGivesTheSameIdAnotherGridAnother) {
    const test::ScratchDir dir;
    const auto grid = sphere(40);
    write_vdb(*grid, dir / "a.vdb");
    const SplatGridId a = id_of(dir / "a.vdb");
    EXPECT_EQ(a, id_of(dir / "a.vdb"));
    EXPECT_EQ(a.file_bytes, std::filesystem::file_size(dir / "a.vdb"));
    EXPECT_FALSE(a.checksum.empty());  // write_vdb() states one
    EXPECT_EQ(a.modified, 0);          // so the time does not matter: a copy is the same grid
    std::filesystem::copy_file(dir / "a.vdb", dir / "copy.vdb");
    EXPECT_EQ(splat_grid_difference(a, id_of(dir / "copy.vdb")), "");

    write_vdb(*sphere(48), dir / "b.vdb");
    EXPECT_NE(splat_grid_difference(a, id_of(dir / "b.vdb")).find("checksum"), std::string::npos);
}

TEST(SplatGridId, OneChangedSampleChangesTheStatedChecksum) {
    const test::ScratchDir dir;
    const auto grid = sphere(40);
    write_vdb(*grid, dir / "a.vdb");
    const SplatGridId before = id_of(dir / "a.vdb");
    grid->tree().setValue(openvdb::Coord(20, 20, 20), grid->tree().getValue(openvdb::Coord(20, 20, 20)) + 0.25f);
    write_vdb(*grid, dir / "a.vdb");
    EXPECT_NE(splat_grid_difference(before, id_of(dir / "a.vdb")).find("checksum"), std::string::npos);
}

TEST(SplatGridId, WithoutAStatedChecksumTheTimeAndTopologyCount) {
    const test::ScratchDir dir;
    const auto grid = sphere(40);
    grid->removeMeta(kMetaChecksum);
    // Another program's file: OpenVDB's own writer, no checksum stated.
    const auto write_foreign = [&](const std::filesystem::path& path, const openvdb::FloatGrid& g) {
        openvdb::io::File file(path.string());
        file.write(openvdb::GridCPtrVec{g.copyGrid()});
        file.close();
    };
    write_foreign(dir / "foreign.vdb", *grid);
    const SplatGridId before = id_of(dir / "foreign.vdb");
    EXPECT_TRUE(before.checksum.empty());
    EXPECT_NE(before.modified, 0);
    std::filesystem::last_write_time(dir / "foreign.vdb", std::filesystem::last_write_time(dir / "foreign.vdb") + std::chrono::seconds(5));
    EXPECT_NE(splat_grid_difference(before, id_of(dir / "foreign.vdb")).find("modified since"), std::string::npos);

    // Another topology at the same size and time: active voxels moved, the hash differs.
    SplatGridId moved = before;
    moved.topology ^= 1;
    EXPECT_EQ(splat_grid_difference(before, moved), "another topology, transform or background");
    const auto shifted = sphere(40);
    shifted->removeMeta(kMetaChecksum);
    shifted->transform().postTranslate(openvdb::Vec3d(1, 0, 0));
    write_foreign(dir / "shifted.vdb", *shifted);
    EXPECT_NE(id_of(dir / "shifted.vdb").topology, before.topology);
}

}  // namespace
}  // namespace vdbmesh
