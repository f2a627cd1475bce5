// STL writer (3D Systems' StereoLithography Interface Specification, 1989): binary
// (80-byte header, uint32 count, per facet a normal, three vertices and a uint16 attribute,
// all little-endian) or ASCII ("solid ... facet normal ... outer loop ... vertex ...").
// Facet normals are computed from the triangles.
#include "io/mesh_io_detail.h"

namespace vdbmesh::detail {
namespace {

// The binary header must not start with "solid": readers would guess ASCII.
constexpr char kBinaryHeader[] = "vdbmesh binary STL";

void write_triple(OutputBuffer& out, const std::array<float, 3>& v) {
    for (int k = 0; k < 3; ++k) {
        out.text(" ");
        out.number(v[k]);
    }
    out.text("\n");
}

}  // namespace

void write_stl_header(OutputBuffer& out, std::uint64_t triangles, bool ascii) {
    if (ascii) {
        out.text("solid vdbmesh\n");
        return;
    }
    std::string header(80, ' ');
    header.replace(0, sizeof kBinaryHeader - 1, kBinaryHeader);
    out.text(header);
    out.binary(std::uint32_t(triangles));
}

void write_stl_facet(OutputBuffer& out, const Corners& corners, bool ascii) {
    if (ascii) {
        out.text("facet normal");
        write_triple(out, facet_normal(corners));
        out.text(" outer loop\n");
        for (const auto& corner : corners) {
            out.text("  vertex");
            write_triple(out, corner);
        }
        out.text(" endloop\nendfacet\n");
        return;
    }
    for (const float c : facet_normal(corners)) out.binary(c);
    for (const auto& corner : corners) {
        for (const float c : corner) out.binary(c);
    }
    out.binary(std::uint16_t(0));
}

void write_stl_footer(OutputBuffer& out, bool ascii) {
    if (ascii) out.text("endsolid vdbmesh\n");
}

void write_stl(const Mesh& mesh, std::ostream& stream, bool ascii) {
    {
        OutputBuffer out(stream);
        write_stl_header(out, mesh.triangles.size(), ascii);
    }
    write_records(stream, mesh.triangles.size(), [&](OutputBuffer& out, std::size_t i) {
        const auto& t = mesh.triangles[i];
        write_stl_facet(out, {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]}, ascii);
    });
    OutputBuffer out(stream);
    write_stl_footer(out, ascii);
}

}  // namespace vdbmesh::detail
