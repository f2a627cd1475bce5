// read_mesh() and write_mesh(): dispatch on the file extension to the per-format code
// (read_stl.cpp, read_ply.cpp, read_obj.cpp, write_stl.cpp, write_ply.cpp, write_obj.cpp).
#include "vdbmesh/mesh_io.h"

#include "io/mesh_io_detail.h"
#include "vdbmesh/checked_output.h"
#include "vdbmesh/error.h"
#include "vdbmesh/parse_util.h"

namespace vdbmesh {
namespace {

enum class MeshFormat { kStl, kPly, kObj };

MeshFormat format_of(const std::filesystem::path& path) {
    const std::string extension = detail::to_lower(path.extension().string());
    if (extension == ".stl") return MeshFormat::kStl;
    if (extension == ".ply") return MeshFormat::kPly;
    if (extension == ".obj") return MeshFormat::kObj;
    throw UsageError(path.string() + ": unknown mesh extension '" + path.extension().string() +
                     "' (expected .stl, .ply or .obj)");
}

}  // namespace

void write_mesh(const Mesh& mesh, const std::filesystem::path& path, const MeshWriteOptions& options) {
    const MeshFormat format = format_of(path);
    for (const auto& t : mesh.triangles) {
        for (const std::uint32_t v : t) {
            if (v >= mesh.vertices.size()) throw Error(path.string() + ": mesh has a vertex index out of range");
        }
    }
    CheckedOutput file(path);
    switch (format) {
        case MeshFormat::kStl: detail::write_stl(mesh, file.stream(), options.ascii); break;
        case MeshFormat::kPly: detail::write_ply(mesh, file.stream(), options.ascii, options.normals); break;
        case MeshFormat::kObj: detail::write_obj(mesh, file.stream(), options.normals); break;
    }
    file.commit();
}

Mesh read_mesh(const std::filesystem::path& path) {
    const MeshFormat format = format_of(path);
    const detail::Bytes bytes = detail::read_prefix(path, detail::file_size_or_throw(path));
    Mesh mesh;
    switch (format) {
        case MeshFormat::kStl: mesh = detail::read_stl(path, bytes); break;
        case MeshFormat::kPly: mesh = detail::read_ply(path, bytes); break;
        case MeshFormat::kObj: mesh = detail::read_obj(path, bytes); break;
    }
    // An OBJ reader skips the statements it does not know, so random bytes or a text file read
    // as no mesh at all rather than as an error; an empty mesh is no valid input anywhere.
    if (mesh.triangles.empty()) {
        const char* records = format == MeshFormat::kObj ? "'f' lines" : format == MeshFormat::kPly ? "faces" : "facets";
        throw FormatError(path.string(), "triangles", std::string("a mesh: at least one triangle (") + records + ")", "none");
    }
    return mesh;
}

std::vector<std::array<float, 3>> vertex_normals(const Mesh& mesh) { return detail::vertex_normals(mesh); }

}  // namespace vdbmesh
