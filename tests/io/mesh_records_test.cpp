// read_mesh_records() (issue 28): the records of a file read as a stream are read_mesh()'s mesh,
// in every format, also for a file larger than the mapped window (whose pages are released
// behind the reading); its errors are read_mesh()'s; a gzip file is refused.
#include <gtest/gtest.h>

#include <zlib.h>

#include <fstream>
#include <functional>
#include <string>

#include "test_data.h"
#include "test_meshes.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh {
namespace {

/// The records as they come: vertices and triangles (PLY, OBJ), facets' corners (STL).
struct Recorder final : MeshRecordVisitor {
    Mesh indexed;
    std::vector<std::array<std::array<float, 3>, 3>> facets;
    void vertex(const std::array<float, 3>& position) override { indexed.vertices.push_back(position); }
    void triangle(const std::array<std::uint32_t, 3>& t) override { indexed.triangles.push_back(t); }
    void facet(const std::array<std::array<float, 3>, 3>& corners) override { facets.push_back(corners); }
};

/// The corners of each triangle of @a mesh.
std::vector<std::array<std::array<float, 3>, 3>> facets_of(const Mesh& mesh) {
    std::vector<std::array<std::array<float, 3>, 3>> facets;
    for (const auto& t : mesh.triangles) facets.push_back({mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]});
    return facets;
}

TEST(MeshRecordsTest, RecordsAreReadMeshsMeshInEveryFormat) {
    const test::ScratchDir dir;
    const Mesh mesh = test::torus(24, 12);
    for (const bool ascii : {false, true}) {
        for (const char* extension : {".ply", ".obj", ".stl"}) {
            const std::filesystem::path file = dir / (std::string(ascii ? "a" : "b") + extension);
            write_mesh(mesh, file, {ascii, false});
            Recorder records;
            read_mesh_records(file, records);
            const Mesh whole = read_mesh(file);
            if (std::string(extension) == ".stl") {
                EXPECT_EQ(records.facets, facets_of(whole)) << file;
                EXPECT_TRUE(records.indexed.vertices.empty());
            } else {
                EXPECT_EQ(records.indexed.vertices, whole.vertices) << file;
                EXPECT_EQ(records.indexed.triangles, whole.triangles) << file;
            }
        }
    }
}

TEST(MeshRecordsTest, FileLargerThanTheWindowReadsWhole) {
    // About 20 MB of ASCII PLY: the mapped window (9 MiB, mapped_file.cpp) is released twice.
    const test::ScratchDir dir;
    const Mesh mesh = test::torus(600, 500);
    write_mesh(mesh, dir / "big.ply", {true, false});
    ASSERT_GT(std::filesystem::file_size(dir / "big.ply"), std::uintmax_t(18) << 20);
    Recorder records;
    read_mesh_records(dir / "big.ply", records);
    EXPECT_EQ(records.indexed.vertices, mesh.vertices);
    EXPECT_EQ(records.indexed.triangles, mesh.triangles);
}

TEST(MeshRecordsTest, BadFilesGiveReadMeshsErrors) {
    const test::ScratchDir dir;
    std::ofstream(dir / "bad_index.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n";
    write_mesh(test::cube(), dir / "cut.ply");
    std::filesystem::resize_file(dir / "cut.ply", std::filesystem::file_size(dir / "cut.ply") - 7);  // the last face cut short
    const auto message = [](const std::function<void()>& read) {
        try {
            read();
        } catch (const FormatError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    Recorder records;
    for (const char* name : {"bad_index.obj", "cut.ply", "missing.ply"}) {
        EXPECT_NE(message([&] { (void)read_mesh(dir / name); }), "no error") << name;
        EXPECT_EQ(message([&] { read_mesh_records(dir / name, records); }), message([&] { (void)read_mesh(dir / name); })) << name;
    }
    const std::string text = "v 0 0 0\nv 1 0 0\n";  // vertices and no face: no mesh
    gzFile gz = gzopen((dir / "points.obj").c_str(), "wb");
    gzwrite(gz, text.data(), unsigned(text.size()));
    gzclose(gz);
    EXPECT_NE(message([&] { read_mesh_records(dir / "points.obj", records); }).find("gunzip"), std::string::npos);
}

}  // namespace
}  // namespace vdbmesh
