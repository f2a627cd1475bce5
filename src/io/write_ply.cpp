// PLY writer (G. Turk, "The PLY Polygon File Format", 1994): vertices x y z as float (and
// nx ny nz with normals), faces as "property list uchar uint vertex_indices"; binary
// little-endian or ASCII.
#include "io/mesh_io_detail.h"

namespace vdbmesh::detail {
namespace {

void write_header(const Mesh& mesh, OutputBuffer& out, bool ascii, bool normals) {
    out.text("ply\nformat ");
    out.text(ascii ? "ascii 1.0\n" : "binary_little_endian 1.0\n");
    out.text("comment written by vdbmesh\nelement vertex ");
    out.number(std::uint64_t(mesh.vertices.size()));
    out.text("\nproperty float x\nproperty float y\nproperty float z\n");
    if (normals) out.text("property float nx\nproperty float ny\nproperty float nz\n");
    out.text("element face ");
    out.number(std::uint64_t(mesh.triangles.size()));
    out.text("\nproperty list uchar uint vertex_indices\nend_header\n");
}

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

void write_ply(const Mesh& mesh, std::ostream& stream, bool ascii, bool normals) {
    OutputBuffer out(stream);
    write_header(mesh, out, ascii, normals);
    const std::vector<std::array<float, 3>> vertex_normal = 
        normals ? vertex_normals(mesh) : std::vector<std::array<float, 3>>{};
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        write_values(out, ascii, mesh.vertices[v], !normals);
        if (normals) write_values(out, ascii, vertex_normal[v], true);
    }
    for (const auto& t : mesh.triangles) {
        if (ascii) {
            out.text("3");
            for (const std::uint32_t v : t) {
                out.text(" ");
                out.number(std::uint64_t(v));
            }
            out.text("\n");
        } else {
            out.binary(std::uint8_t(3));
            for (const std::uint32_t v : t) out.binary(v);
        }
    }
}

}  // namespace vdbmesh::detail
