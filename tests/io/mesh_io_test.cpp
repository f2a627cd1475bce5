// read_mesh() / write_mesh(): round trips in every format and mode, hand-written files of the
// variants other programs write, malformed files, and the real zippered Stanford bunny.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>

#include "test_data.h"
#include "test_meshes.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh {
namespace {

using test::ScratchDir;

void write_text(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

/// The corners' coordinates, triangle by triangle: what STL keeps of a mesh.
std::vector<std::array<float, 3>> corner_positions(const Mesh& mesh) {
    std::vector<std::array<float, 3>> corners;
    for (const auto& t : mesh.triangles) {
        for (const std::uint32_t v : t) corners.push_back(mesh.vertices[v]);
    }
    return corners;
}

/// The torus has float coordinates that need all their digits, and every vertex is used.
const Mesh& sample_mesh() {
    static const Mesh mesh = test::torus(12, 7, 3.3, 1.1);
    return mesh;
}

TEST(MeshIoTest, IndexedFormatsRoundTripExactly) {
    const ScratchDir dir;
    const std::vector<std::pair<std::string, MeshWriteOptions>> cases = {
        {"binary.ply", {}}, {"ascii.ply", {true, false}}, {"normals.ply", {false, true}},
        {"ascii_normals.ply", {true, true}}, {"plain.obj", {}}, {"normals.obj", {false, true}}};
    for (const auto& [name, options] : cases) {
        write_mesh(sample_mesh(), dir / name, options);
        const Mesh back = read_mesh(dir / name);
        EXPECT_EQ(back.vertices, sample_mesh().vertices) << name;
        EXPECT_EQ(back.triangles, sample_mesh().triangles) << name;
    }
}

std::string file_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// Issue 28: a mesh written as a stream is byte for byte what write_mesh() writes.
TEST(MeshIoTest, StreamWriterWritesWriteMeshsBytes) {
    const ScratchDir dir;
    const Mesh& mesh = sample_mesh();
    const std::vector<std::pair<std::string, MeshWriteOptions>> cases = {
        {"binary.stl", {}}, {"ascii.stl", {true, false}}, {"binary.ply", {}}, {"ascii.ply", {true, false}}, {"plain.obj", {}}};
    for (const auto& [name, options] : cases) {
        write_mesh(mesh, dir / ("whole_" + name), options);
        MeshStreamWriter stream(dir / ("stream_" + name), options, mesh.vertices.size(), mesh.triangles.size());
        for (const auto& v : mesh.vertices) stream.add_vertex(v);
        for (const auto& t : mesh.triangles) stream.add_triangle(t, {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]});
        stream.commit();
        EXPECT_EQ(file_bytes(dir / ("stream_" + name)), file_bytes(dir / ("whole_" + name))) << name;
    }
}

TEST(MeshIoTest, StreamWriterRefusesWhatItCannotWriteAndLeavesNoFile) {
    const ScratchDir dir;
    EXPECT_THROW(MeshStreamWriter(dir / "normals.ply", {false, true}, 3, 1), UsageError);
    EXPECT_THROW(MeshStreamWriter(dir / "mesh.xyz", {}, 3, 1), UsageError);
    {
        MeshStreamWriter short_of_triangles(dir / "short.ply", {}, 3, 2);
        for (int v = 0; v < 3; ++v) short_of_triangles.add_vertex({float(v), float(v * v), 0});
        EXPECT_THROW(short_of_triangles.add_triangle({0, 1, 3}, {}), Error);  // vertex 3 of 3
        short_of_triangles.add_triangle({0, 1, 2}, {});
        EXPECT_THROW(short_of_triangles.add_vertex({0, 0, 0}), Error);  // after a triangle
        EXPECT_THROW(short_of_triangles.commit(), Error);  // one triangle of two
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(MeshIoTest, StlRoundTripsWeldingBitIdenticalCorners) {
    const ScratchDir dir;
    for (const bool ascii : {false, true}) {
        const auto path = dir / (ascii ? "ascii.stl" : "binary.stl");
        write_mesh(sample_mesh(), path, {ascii, false});
        const Mesh back = read_mesh(path);
        EXPECT_EQ(back.vertices.size(), sample_mesh().vertices.size()) << path;
        EXPECT_EQ(corner_positions(back), corner_positions(sample_mesh())) << path;
        EXPECT_TRUE(analyze_mesh(back).is_clean()) << path;
    }
}

TEST(MeshIoTest, StlWeldsOnlyBitIdenticalCoordinates) {
    // Two triangles whose shared edge differs by one float ulp at one end stay unwelded there.
    const float nudged = std::nextafter(1.0f, 2.0f);
    const Mesh soup = test::triangle_soup({{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {{{nudged, 0, 0}, {1, 1, 0}, {0, 1, 0}}}});
    const ScratchDir dir;
    write_mesh(soup, dir / "nudged.stl");
    EXPECT_EQ(read_mesh(dir / "nudged.stl").vertices.size(), 5u);
}

TEST(MeshIoTest, BinaryStlStartingWithSolidIsReadAsBinary) {
    const ScratchDir dir;
    write_mesh(test::tetrahedron(), dir / "t.stl");
    std::fstream file(dir / "t.stl", std::ios::in | std::ios::out | std::ios::binary);
    file.write("solid but binary", 16);
    file.close();
    const Mesh back = read_mesh(dir / "t.stl");
    EXPECT_EQ(back.triangles.size(), 4u);
    EXPECT_EQ(back.vertices.size(), 4u);
}

TEST(MeshIoTest, StlNormalsComeFromTheTriangles) {
    const ScratchDir dir;
    write_mesh(test::tetrahedron(), dir / "t.stl", {true, false});
    std::ifstream in(dir / "t.stl");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("facet normal 0 0 -1"), std::string::npos);
    EXPECT_NE(text.find("facet normal 0.57735026 0.57735026 0.57735026"), std::string::npos);
}

TEST(MeshIoTest, PlyVariantsOfOtherWriters) {
    const ScratchDir dir;
    // ASCII, double coordinates, an extra vertex property, int count type, a quad, and an
    // extra element with a list, all of which must be read past.
    write_text(dir / "quad.ply",
               "ply\r\nformat ascii 1.0\r\ncomment hand-made\r\nelement vertex 4\r\nproperty double x\r\n"
               "property double y\r\nproperty float confidence\r\nproperty double z\r\nelement face 1\r\n"
               "property list int uint vertex_index\r\nelement edge 1\r\nproperty list uchar int v\r\n"
               "end_header\r\n0 0 1 0\n1 0 1 0\n1 1 1 0\n0 1 1 0\n4 0 1 2 3\n2 0 2\n");
    const Mesh quad = read_mesh(dir / "quad.ply");
    ASSERT_EQ(quad.vertices.size(), 4u);
    EXPECT_EQ(quad.triangles, (std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}}));
    EXPECT_EQ(quad.vertices[2], (std::array<float, 3>{1, 1, 0}));

    // Binary big-endian: one triangle, float coordinates, ushort count, short indices.
    std::string be = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 1\nproperty list ushort short vertex_indices\nend_header\n";
    const float coords[9] = {0, 0, 0, 2, 0, 0, 0, 3, 0.5f};
    for (const float c : coords) {
        unsigned char raw[4];
        std::memcpy(raw, &c, 4);
        be.append({char(raw[3]), char(raw[2]), char(raw[1]), char(raw[0])});
    }
    be.append({0, 3, 0, 0, 0, 1, 0, 2});
    write_text(dir / "be.ply", be);
    const Mesh triangle = read_mesh(dir / "be.ply");
    ASSERT_EQ(triangle.vertices.size(), 3u);
    EXPECT_EQ(triangle.vertices[2], (std::array<float, 3>{0, 3, 0.5f}));
    EXPECT_EQ(triangle.triangles, (std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}}));
}

TEST(MeshIoTest, PlyElementWithoutPropertiesIsSkippedWhateverItsCount) {
    // Found by tests/fuzz/fuzz_ply.cpp: such an element was walked one (empty) element at a
    // time, so a count of 9e18 hung the reader; it takes no bytes, whatever its count.
    const ScratchDir dir;
    write_text(dir / "marker.ply",
               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
               "element marker 9000000000000000000\nelement face 1\nproperty list uchar int vertex_indices\n"
               "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    const Mesh mesh = read_mesh(dir / "marker.ply");
    EXPECT_EQ(mesh.vertices.size(), 3u);
    EXPECT_EQ(mesh.triangles, (std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}}));
}

TEST(MeshIoTest, ObjCornerFormsAndNegativeIndices) {
    const ScratchDir dir;
    write_text(dir / "forms.obj",
               "# comment\nmtllib x.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0 1.0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
               "g group\nusemtl m\nf 1/1/1 2/1/1 3/1/1\nf -4//1 -2//1 -1//1\ns off\nv 0 0 1\nf 1/1 2 -1\n");
    const Mesh mesh = read_mesh(dir / "forms.obj");
    EXPECT_EQ(mesh.vertices.size(), 5u);
    EXPECT_EQ(mesh.triangles, (std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}, {0, 1, 4}}));
}

TEST(MeshIoTest, TruncatedBinaryStlIsAFormatError) {
    const ScratchDir dir;
    write_mesh(test::cube(), dir / "cube.stl");
    std::filesystem::resize_file(dir / "cube.stl", 84 + 50 * 11 + 20);
    try {
        read_mesh(dir / "cube.stl");
        FAIL() << "no exception";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("file size"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("684"), std::string::npos) << e.what();  // 84 + 50 x 12
    }
}

TEST(MeshIoTest, MalformedFilesAreFormatErrors) {
    const ScratchDir dir;
    const std::string header3 = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::vector<std::pair<std::string, std::string>> cases = {
        // More vertices announced than present.
        {"count.ply", "ply\nformat ascii 1.0\nelement vertex 10\nproperty float x\nproperty float y\n"
                      "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n"},
        // Fewer vertices announced than present: the rest does not parse as faces.
        {"fewer.ply", header3 + "0 0 0\n1 0 0\n0 1 0\n5 5 5\n3 0 1 2\n"},
        {"index.ply", header3 + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"},
        {"twogon.ply", header3 + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n"},
        {"number.ply", header3 + "0 0 zero\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"},
        {"magic.ply", "plx\n"},
        {"format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"},
        {"binary.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
                       "property float y\nproperty float z\nend_header\n0123456789ab"},
        {"stl.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n"},
        {"short.stl", "tiny"},
        {"obj.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n"},
        {"objzero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"},
        {"objnum.obj", "v 0 0 nan\n"},
    };
    for (const auto& [name, text] : cases) {
        write_text(dir / name, text);
        EXPECT_THROW(read_mesh(dir / name), FormatError) << name;
    }
    EXPECT_THROW(read_mesh(dir / "missing.ply"), FormatError);
}

TEST(MeshIoTest, UnknownExtensionIsAUsageError) {
    const ScratchDir dir;
    EXPECT_THROW(write_mesh(test::cube(), dir / "cube.off"), UsageError);
    EXPECT_THROW(read_mesh(dir / "cube.off"), UsageError);
}

TEST(MeshIoTest, FailedWriteLeavesNoFile) {
    const ScratchDir dir;
    EXPECT_THROW(write_mesh(test::cube(), dir / "missing_folder" / "cube.stl"), Error);
    EXPECT_FALSE(std::filesystem::exists(dir / "missing_folder"));
}

TEST(MeshIoTest, ZipperedBunnyReads) {
    VDBMESH_SHARED_DATA(path, "pointcloud_stanford_bunny_scans/reconstruction/bun_zipper.ply");
    const Mesh bunny = read_mesh(path);
    EXPECT_EQ(bunny.vertices.size(), 35947u);
    EXPECT_EQ(bunny.triangles.size(), 69451u);
    const MeshAnalysis r = analyze_mesh(bunny);
    // The zippered bunny is open at its base (holes the scanner could not see).
    EXPECT_FALSE(r.closed);
    EXPECT_GT(r.boundary_edges, 0u);
    std::cout << "bun_zipper.ply: boundary edges " << r.boundary_edges << " in " << r.boundary_loops
              << " loops, non-manifold edges " << r.nonmanifold_edges << ", vertices " << r.nonmanifold_vertices
              << ", misoriented " << r.misoriented_edges << ", degenerate " << r.degenerate_faces
              << ", self-intersecting pairs " << r.self_intersecting_pairs << ", components " << r.components
              << ", genus " << r.genus << ", area " << r.area << ", volume " << r.volume << ", min angle "
              << r.min_angle_deg << "\n";
}

}  // namespace
}  // namespace vdbmesh
