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

void write_obj(const Mesh& mesh, std::ostream& stream, bool normals) {
    OutputBuffer out(stream);
    out.text("# written by vdbmesh\n");
    for (const auto& v : mesh.vertices) write_line(out, "v", v);
    if (normals) {
        for (const auto& n : vertex_normals(mesh)) write_line(out, "vn", n);
    }
    for (const auto& t : mesh.triangles) {
        out.text("f");
        for (const std::uint32_t v : t) {
            out.text(" ");
            out.number(std::uint64_t(v) + 1);
            if (normals) {
                out.text("//");
                out.number(std::uint64_t(v) + 1);
            }
        }
        out.text("\n");
    }
}

}  // namespace vdbmesh::detail
