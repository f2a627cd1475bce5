// PLY writer (G. Turk, "The PLY Polygon File Format", 1994): vertices x y z as float (and
// nx ny nz with normals), faces as "property list uchar uint vertex_indices"; binary
// little-endian or ASCII.
#include "io/mesh_io_detail.h"

namespace vdbmesh::detail {
namespace {

void write_values(OutputBuffer& out, bool ascii, const std::array<float, 3>& values, bool last) {
    for (int k = 0; k < 3; ++k) {
        if (ascii) {
            out.number(values[k]);
            out.text(k == 2 && last ? "\n" : " ");
        } else {
            out.binary(values[k]);
        }
    }
}

}  // namespace

void write_ply_header(OutputBuffer& out, std::uint64_t vertices, std::uint64_t triangles, bool ascii, bool normals) {
    out.text("ply\nformat ");
    out.text(ascii ? "ascii 1.0\n" : "binary_little_endian 1.0\n");
    out.text("comment written by vdbmesh\nelement vertex ");
    out.number(vertices);
    out.text("\nproperty float x\nproperty float y\nproperty float z\n");
    if (normals) out.text("property float nx\nproperty float ny\nproperty float nz\n");
    out.text("element face ");
    out.number(triangles);
    out.text("\nproperty list uchar uint vertex_indices\nend_header\n");
}

void write_ply_vertex(OutputBuffer& out, const std::array<float, 3>& position, const std::array<float, 3>* normal, bool ascii) {
    write_values(out, ascii, position, !normal);
    if (normal) write_values(out, ascii, *normal, true);
}

void write_ply_face(OutputBuffer& out, const std::array<std::uint32_t, 3>& triangle, bool ascii) {
    if (ascii) {
        out.text("3");
        for (const std::uint32_t v : triangle) {
            out.text(" ");
            out.number(std::uint64_t(v));
        }
        out.text("\n");
    } else {
        out.binary(std::uint8_t(3));
        for (const std::uint32_t v : triangle) out.binary(v);
    }
}

void write_ply(const Mesh& mesh, std::ostream& stream, bool ascii, bool normals) {
    {
        OutputBuffer out(stream);
        write_ply_header(out, mesh.vertices.size(), mesh.triangles.size(), ascii, normals);
    }
    const std::vector<std::array<float, 3>> vertex_normal = normals ? detail::vertex_normals(mesh) : std::vector<std::array<float, 3>>{};
    write_records(stream, mesh.vertices.size(), [&](OutputBuffer& out, std::size_t v) {
        write_ply_vertex(out, mesh.vertices[v], normals ? &vertex_normal[v] : nullptr, ascii);
    });
    write_records(stream, mesh.triangles.size(), [&](OutputBuffer& out, std::size_t t) { write_ply_face(out, mesh.triangles[t], ascii); });
}

}  // namespace vdbmesh::detail
