// Wavefront OBJ writer (Wavefront Technologies, "Appendix B1: Object Files (.obj)"):
// "v x y z", optionally "vn nx ny nz", and "f a b c" (1-based; "a//a" with normals).
#include "io/mesh_io_detail.h"

namespace vdbmesh::detail {
namespace {

void write_line(OutputBuffer& out, std::string_view keyword, const std::array<float, 3>& v) {
    out.text(keyword);
    for (int k = 0; k < 3; ++k) {
        out.text(" ");
        out.number(v[k]);
    }
    out.text("\n");
}

}  // namespace

void write_obj_header(OutputBuffer& out) { out.text("# written by vdbmesh\n"); }
void write_obj_vertex(OutputBuffer& out, const std::array<float, 3>& position) { write_line(out, "v", position); }
void write_obj_normal(OutputBuffer& out, const std::array<float, 3>& normal) { write_line(out, "vn", normal); }

void write_obj_face(OutputBuffer& out, const std::array<std::uint32_t, 3>& triangle, bool normals) {
    out.text("f");
    for (const std::uint32_t v : triangle) {
        out.text(" ");
        out.number(std::uint64_t(v) + 1);
        if (normals) {
            out.text("//");
            out.number(std::uint64_t(v) + 1);
        }
    }
    out.text("\n");
}

void write_obj(const Mesh& mesh, std::ostream& stream, bool normals) {
    {
        OutputBuffer out(stream);
        write_obj_header(out);
    }
    write_records(stream, mesh.vertices.size(), [&](OutputBuffer& out, std::size_t v) { write_obj_vertex(out, mesh.vertices[v]); });
    if (normals) {
        const std::vector<std::array<float, 3>> vertex_normal = detail::vertex_normals(mesh);
        write_records(stream, vertex_normal.size(), [&](OutputBuffer& out, std::size_t v) { write_obj_normal(out, vertex_normal[v]); });
    }
    write_records(stream, mesh.triangles.size(), [&](OutputBuffer& out, std::size_t t) { write_obj_face(out, mesh.triangles[t], normals); });
}

}  // namespace vdbmesh::detail
