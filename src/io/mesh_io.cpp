// read_mesh() and write_mesh(): dispatch on the file extension to the per-format code
// (read_stl.cpp, read_ply.cpp, read_obj.cpp, write_stl.cpp, write_ply.cpp, write_obj.cpp).
#include "vdbmesh/mesh_io.h"

#include "io/mapped_file.h"
#include "io/mesh_io_detail.h"
#include "vdbmesh/checked_output.h"
#include "vdbmesh/error.h"
#include "vdbmesh/parse_util.h"

#include <string>

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

struct MeshStreamWriter::Stream {
    Stream(const std::filesystem::path& path, const MeshWriteOptions& options, std::uint64_t vertices, std::uint64_t triangles)
        : target(path), format(format_of(path)), ascii(options.ascii), vertex_count(vertices), triangle_count(triangles), file(path),
          out(file.stream()) {}
    std::filesystem::path target;
    MeshFormat format;
    bool ascii;
    std::uint64_t vertex_count, triangle_count;
    std::uint64_t vertices_written = 0, triangles_written = 0;
    CheckedOutput file;
    detail::OutputBuffer out;
};

MeshStreamWriter::MeshStreamWriter(const std::filesystem::path& path, const MeshWriteOptions& options, std::uint64_t vertex_count,
                                   std::uint64_t triangle_count) {
    if (options.normals) throw UsageError(path.string() + ": per-vertex normals are not available when the mesh is written as a stream");
    format_of(path);  // an unknown extension is refused before the file is made
    stream_ = std::make_unique<Stream>(path, options, vertex_count, triangle_count);
    Stream& s = *stream_;
    switch (s.format) {
        case MeshFormat::kStl: detail::write_stl_header(s.out, triangle_count, s.ascii); break;
        case MeshFormat::kPly: detail::write_ply_header(s.out, vertex_count, triangle_count, s.ascii, false); break;
        case MeshFormat::kObj: detail::write_obj_header(s.out); break;
    }
}

MeshStreamWriter::~MeshStreamWriter() = default;

void MeshStreamWriter::add_vertex(const std::array<float, 3>& position) {
    Stream& s = *stream_;
    if (s.triangles_written > 0 || s.vertices_written == s.vertex_count) {
        throw Error(s.target.string() + ": a vertex beyond the " + std::to_string(s.vertex_count) + " announced, or after a triangle");
    }
    ++s.vertices_written;
    if (s.format == MeshFormat::kPly) detail::write_ply_vertex(s.out, position, nullptr, s.ascii);
    else if (s.format == MeshFormat::kObj) detail::write_obj_vertex(s.out, position);
}

bool MeshStreamWriter::writes_corners(const std::filesystem::path& path) { return format_of(path) == MeshFormat::kStl; }

void MeshStreamWriter::add_triangle(const std::array<std::uint32_t, 3>& triangle, const std::array<std::array<float, 3>, 3>& corners) {
    Stream& s = *stream_;
    if (s.triangles_written == s.triangle_count) throw Error(s.target.string() + ": a triangle beyond the " + std::to_string(s.triangle_count) + " announced");
    for (const std::uint32_t v : triangle) {
        if (v >= s.vertex_count) throw Error(s.target.string() + ": mesh has a vertex index out of range");
    }
    ++s.triangles_written;
    switch (s.format) {
        case MeshFormat::kStl: detail::write_stl_facet(s.out, corners, s.ascii); break;
        case MeshFormat::kPly: detail::write_ply_face(s.out, triangle, s.ascii); break;
        case MeshFormat::kObj: detail::write_obj_face(s.out, triangle, false); break;
    }
}

void MeshStreamWriter::commit() {
    Stream& s = *stream_;
    if (s.vertices_written != s.vertex_count || s.triangles_written != s.triangle_count) {
        throw Error(s.target.string() + ": " + std::to_string(s.vertices_written) + " vertices and " + std::to_string(s.triangles_written) +
                    " triangles written, " + std::to_string(s.vertex_count) + " and " + std::to_string(s.triangle_count) + " announced");
    }
    if (s.format == MeshFormat::kStl) detail::write_stl_footer(s.out, s.ascii);
    s.out.flush();
    s.file.commit();
}

MeshRecordFormat::MeshRecordFormat(const std::filesystem::path& path, bool ascii) : format_(int(format_of(path))), ascii_(ascii) {}

std::string MeshRecordFormat::header(std::uint64_t vertex_count, std::uint64_t triangle_count) const {
    std::string bytes;
    detail::OutputBuffer out(bytes);
    switch (MeshFormat(format_)) {
        case MeshFormat::kStl: detail::write_stl_header(out, triangle_count, ascii_); break;
        case MeshFormat::kPly: detail::write_ply_header(out, vertex_count, triangle_count, ascii_, false); break;
        case MeshFormat::kObj: detail::write_obj_header(out); break;
    }
    return bytes;
}

std::string MeshRecordFormat::footer() const {
    std::string bytes;
    detail::OutputBuffer out(bytes);
    if (MeshFormat(format_) == MeshFormat::kStl) detail::write_stl_footer(out, ascii_);
    return bytes;
}

void MeshRecordFormat::vertices(const std::vector<std::array<float, 3>>& positions, std::string& out) const {
    detail::OutputBuffer buffer(out);
    for (const std::array<float, 3>& p : positions) {
        if (MeshFormat(format_) == MeshFormat::kPly) detail::write_ply_vertex(buffer, p, nullptr, ascii_);
        else if (MeshFormat(format_) == MeshFormat::kObj) detail::write_obj_vertex(buffer, p);
    }
}

void MeshRecordFormat::triangles(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                 const std::vector<std::array<std::array<float, 3>, 3>>& corners, std::string& out) const {
    detail::OutputBuffer buffer(out);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        switch (MeshFormat(format_)) {
            case MeshFormat::kStl: detail::write_stl_facet(buffer, corners.at(t), ascii_); break;
            case MeshFormat::kPly: detail::write_ply_face(buffer, triangles[t], ascii_); break;
            case MeshFormat::kObj: detail::write_obj_face(buffer, triangles[t], false); break;
        }
    }
}

namespace {

void read_records(MeshFormat format, const std::filesystem::path& path, const detail::ByteView& bytes, MeshRecordVisitor& visitor) {
    switch (format) {
        case MeshFormat::kStl: detail::read_stl_records(path, bytes, visitor); break;
        case MeshFormat::kPly: detail::read_ply_records(path, bytes, visitor); break;
        case MeshFormat::kObj: detail::read_obj_records(path, bytes, visitor); break;
    }
}

// An OBJ reader skips the statements it does not know, so random bytes or a text file read
// as no mesh at all rather than as an error; an empty mesh is no valid input anywhere.
FormatError no_triangle_error(const std::filesystem::path& path, MeshFormat format) {
    const char* records = format == MeshFormat::kObj ? "'f' lines" : format == MeshFormat::kPly ? "faces" : "facets";
    return FormatError(path.string(), "triangles", std::string("a mesh: at least one triangle (") + records + ")", "none");
}

/// Passes the records on, noting whether a triangle came.
class TriangleWitness final : public MeshRecordVisitor {
public:
    explicit TriangleWitness(MeshRecordVisitor& next) : next_(next) {}
    void announced(std::uint64_t vertices, std::uint64_t faces) override { next_.announced(vertices, faces); }
    void vertex(const std::array<float, 3>& position) override { next_.vertex(position); }
    void triangle(const std::array<std::uint32_t, 3>& t) override { any = true, next_.triangle(t); }
    void facet(const detail::Corners& corners) override { any = true, next_.facet(corners); }
    bool any = false;

private:
    MeshRecordVisitor& next_;
};

}  // namespace

Mesh read_mesh(const std::filesystem::path& path) {
    const MeshFormat format = format_of(path);
    const detail::Bytes bytes = detail::read_prefix(path, detail::file_size_or_throw(path));
    Mesh mesh;
    switch (format) {
        case MeshFormat::kStl: mesh = detail::read_stl(path, bytes); break;
        case MeshFormat::kPly: mesh = detail::read_ply(path, bytes); break;
        case MeshFormat::kObj: mesh = detail::read_obj(path, bytes); break;
    }
    if (mesh.triangles.empty()) throw no_triangle_error(path, format);
    return mesh;
}

void read_mesh_records(const std::filesystem::path& path, MeshRecordVisitor& visitor) {
    const MeshFormat format = format_of(path);
    detail::file_size_or_throw(path);  // the message read_mesh() gives for a missing file
    detail::MappedFile file(path);
    if (file.size() >= 2 && file.data()[0] == 0x1f && file.data()[1] == 0x8b) {
        throw FormatError(path.string(), "encoding", "an uncompressed file (a gzip file cannot be read as a stream; gunzip it first)",
                          "gzip");
    }
    TriangleWitness witness(visitor);
    read_records(format, path, detail::ByteView(file.data(), file.size(), &file), witness);
    if (!witness.any) throw no_triangle_error(path, format);
}

std::vector<std::array<float, 3>> vertex_normals(const Mesh& mesh) { return detail::vertex_normals(mesh); }

}  // namespace vdbmesh
