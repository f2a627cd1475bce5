// STL writer (3D Systems' StereoLithography Interface Specification, 1989): binary
// (80-byte header, uint32 count, per facet a normal, three vertices and a uint16 attribute,
// all little-endian) or ASCII ("solid ... facet normal ... outer loop ... vertex ...").
// Facet normals are computed from the triangles.
#include "io/mesh_io_detail.h"

namespace vdbmesh::detail {
namespace {

// The binary header must not start with "solid": readers would guess ASCII.
constexpr char kBinaryHeader[] = "vdbmesh binary STL";

void write_binary(const Mesh& mesh, OutputBuffer& out) {
    std::string header(80, ' ');
    header.replace(0, sizeof kBinaryHeader - 1, kBinaryHeader);
    out.text(header);
    out.binary(std::uint32_t(mesh.triangles.size()));
    for (const auto& t : mesh.triangles) {
        for (const float c : facet_normal(mesh, t)) out.binary(c);
        for (const std::uint32_t v : t) {
            for (const float c : mesh.vertices[v]) out.binary(c);
        }
        out.binary(std::uint16_t(0));
    }
}

void write_triple(OutputBuffer& out, const std::array<float, 3>& v) {
    for (int k = 0; k < 3; ++k) {
        out.text(" ");
        out.number(v[k]);
    }
    out.text("\n");
}

void write_ascii(const Mesh& mesh, OutputBuffer& out) {
    out.text("solid vdbmesh\n");
    for (const auto& t : mesh.triangles) {
        out.text("facet normal");
        write_triple(out, facet_normal(mesh, t));
        out.text(" outer loop\n");
        for (const std::uint32_t v : t) {
            out.text("  vertex");
            write_triple(out, mesh.vertices[v]);
        }
        out.text(" endloop\nendfacet\n");
    }
    out.text("endsolid vdbmesh\n");
}

}  // namespace

void write_stl(const Mesh& mesh, std::ostream& stream, bool ascii) {
    OutputBuffer out(stream);
    if (ascii) {
        write_ascii(mesh, out);
    } else {
        write_binary(mesh, out);
    }
}

}  // namespace vdbmesh::detail
