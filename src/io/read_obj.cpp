// Wavefront OBJ reader (Wavefront Technologies, "Appendix B1: Object Files (.obj)"):
// "v x y z [w]" and "f" with corners a, a/b, a/b/c or a//c, 1-based, negative indices
// counting back from the last vertex so far; polygons are triangulated as fans. Every other
// statement (vt, vn, g, o, s, usemtl, mtllib, l, p ...) is ignored.
#include <limits>
#include <string>

#include "io/mesh_io_detail.h"
#include "vdbmesh/parse_util.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {
namespace {

std::string as_quoted(std::string_view text) { return text.empty() ? "nothing" : "'" + std::string(text) + "'"; }

/// Vertices so far: the range of an index.
void read_vertex(const std::filesystem::path& file, const std::vector<std::string>& words, std::size_t line, std::uint64_t& vertices,
                 MeshRecordVisitor& visitor) {
    if (words.size() < 4 || words.size() > 5) {
        throw FormatError(file.string(), "line " + std::to_string(line) + ": v", "3 or 4 numbers",
                          std::to_string(words.size() - 1) + " values");
    }
    std::array<float, 3> vertex{};
    for (int k = 0; k < 3; ++k) {
        if (!parse_float(words[1 + k], vertex[k])) {
            throw FormatError(file.string(), "line " + std::to_string(line) + ": v", "a finite number", as_quoted(words[1 + k]));
        }
    }
    if (vertices == std::numeric_limits<std::uint32_t>::max()) {
        throw FormatError(file.string(), "line " + std::to_string(line) + ": v", "at most 2^32 - 1 vertices", "more");
    }
    ++vertices;
    visitor.vertex(vertex);
}

/// The vertex of a corner "a", "a/b", "a/b/c" or "a//c" (1-based or negative).
std::uint32_t corner_vertex(const std::filesystem::path& file, std::string_view corner, std::size_t line,
                            std::uint64_t vertices) {
    const std::string_view text = corner.substr(0, corner.find('/'));
    std::int64_t index = 0;
    const std::int64_t count = std::int64_t(vertices);
    if (!parse_integer(text, index) || index == 0 || index > count || index < -count) {
        throw FormatError(file.string(), "line " + std::to_string(line) + ": f vertex index",
                          count > 0 ? "1 .. " + std::to_string(count) + " or -1 .. -" + std::to_string(count)
                                    : "a vertex defined before the face",
                          as_quoted(text));
    }
    return std::uint32_t(index > 0 ? index - 1 : count + index);
}

void read_face(const std::filesystem::path& file, const std::vector<std::string>& words, std::size_t line, std::uint64_t vertices,
               MeshRecordVisitor& visitor) {
    if (words.size() < 4) {
        throw FormatError(file.string(), "line " + std::to_string(line) + ": f", "at least 3 corners",
                          std::to_string(words.size() - 1));
    }
    const std::uint32_t first = corner_vertex(file, words[1], line, vertices);
    std::uint32_t previous = corner_vertex(file, words[2], line, vertices);
    for (std::size_t k = 3; k < words.size(); ++k) {
        const std::uint32_t next = corner_vertex(file, words[k], line, vertices);
        visitor.triangle({first, previous, next});
        previous = next;
    }
}

}  // namespace

void read_obj_records(const std::filesystem::path& file, const ByteView& bytes, MeshRecordVisitor& visitor) {
    TextCursor cursor(bytes);
    std::string_view text;
    std::uint64_t vertices = 0;
    for (std::size_t line = cursor.line_number(); cursor.line(text); line = cursor.line_number()) {
        bytes.done_before(cursor.offset());
        const std::size_t comment = text.find('#');
        const std::vector<std::string> words = split_words(text.substr(0, comment));
        if (words.empty()) continue;
        if (words[0] == "v") read_vertex(file, words, line, vertices, visitor);
        if (words[0] == "f") read_face(file, words, line, vertices, visitor);
    }
}

Mesh read_obj(const std::filesystem::path& file, const Bytes& bytes) {
    MeshBuilder builder;
    read_obj_records(file, bytes, builder);
    return std::move(builder.mesh);
}

}  // namespace vdbmesh::detail
