#pragma once
// Private: the per-format readers and writers behind read_mesh() / write_mesh(), and the
// byte and text helpers they share.

#include <array>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "vdbmesh/mesh.h"
#include "vdbmesh/mesh_io.h"

#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the mesh readers and writers assume a little-endian host"
#endif

namespace vdbmesh::detail {

using Bytes = std::vector<unsigned char>;

class OutputBuffer;
/// A triangle's three corners, in its order.
using Corners = std::array<std::array<float, 3>, 3>;

// Each format as records, which write_mesh() and MeshStreamWriter both write (the same bytes).
void write_stl_header(OutputBuffer& out, std::uint64_t triangles, bool ascii);
void write_stl_facet(OutputBuffer& out, const Corners& corners, bool ascii);
void write_stl_footer(OutputBuffer& out, bool ascii);
void write_ply_header(OutputBuffer& out, std::uint64_t vertices, std::uint64_t triangles, bool ascii, bool normals);
/// A vertex, and its normal when @a normal is not null.
void write_ply_vertex(OutputBuffer& out, const std::array<float, 3>& position, const std::array<float, 3>* normal, bool ascii);
void write_ply_face(OutputBuffer& out, const std::array<std::uint32_t, 3>& triangle, bool ascii);
void write_obj_header(OutputBuffer& out);
void write_obj_vertex(OutputBuffer& out, const std::array<float, 3>& position);
void write_obj_normal(OutputBuffer& out, const std::array<float, 3>& normal);
void write_obj_face(OutputBuffer& out, const std::array<std::uint32_t, 3>& triangle, bool normals);

/// Writes records [0, @a count) to @a out in order, record i formatted by @a write(buffer, i):
/// formatted in parallel, a batch of chunks at a time (the bytes do not depend on the threads).
/// The buffer of each chunk is its own: @a write must not keep state between records.
void write_records(std::ostream& out, std::size_t count, const std::function<void(OutputBuffer&, std::size_t)>& write);

void write_stl(const Mesh& mesh, std::ostream& out, bool ascii);
void write_ply(const Mesh& mesh, std::ostream& out, bool ascii, bool normals);
void write_obj(const Mesh& mesh, std::ostream& out, bool normals);

/// A file's bytes as the readers walk them: a whole buffer (read_mesh()) or a mapped file
/// whose pages behind the reading are released (read_mesh_records()).
class ByteView {
public:
    ByteView(const Bytes& bytes) : data_(bytes.data()), size_(bytes.size()) {}  // implicit: a whole buffer is one view
    ByteView(const unsigned char* data, std::size_t size, class MappedFile* mapping) : data_(data), size_(size), mapping_(mapping) {}
    const unsigned char* data() const { return data_; }
    std::size_t size() const { return size_; }
    unsigned char operator[](std::size_t i) const { return data_[i]; }
    /// The reader will not read before @a offset again (called between records).
    void done_before(std::size_t offset) const;

private:
    const unsigned char* data_;
    std::size_t size_;
    class MappedFile* mapping_ = nullptr;
};

// Each format as records (the one parser of each; read_mesh() builds its Mesh from them).
void read_stl_records(const std::filesystem::path& file, const ByteView& bytes, MeshRecordVisitor& visitor);
void read_ply_records(const std::filesystem::path& file, const ByteView& bytes, MeshRecordVisitor& visitor);
void read_obj_records(const std::filesystem::path& file, const ByteView& bytes, MeshRecordVisitor& visitor);

/// read_mesh()'s visitor for PLY and OBJ: the records into a Mesh (read_stl() welds its facets).
struct MeshBuilder final : MeshRecordVisitor {
    Mesh mesh;
    void announced(std::uint64_t vertices, std::uint64_t faces) override {
        mesh.vertices.reserve(vertices);
        mesh.triangles.reserve(faces);
    }
    void vertex(const std::array<float, 3>& position) override { mesh.vertices.push_back(position); }
    void triangle(const std::array<std::uint32_t, 3>& triangle) override { mesh.triangles.push_back(triangle); }
    void facet(const Corners&) override {}
};

Mesh read_stl(const std::filesystem::path& file, const Bytes& bytes);
Mesh read_ply(const std::filesystem::path& file, const Bytes& bytes);
Mesh read_obj(const std::filesystem::path& file, const Bytes& bytes);

/// Unit normal of each vertex: the area-weighted average of its triangles' normals (0 when none).
std::vector<std::array<float, 3>> vertex_normals(const Mesh& mesh);
/// Unit normal of a triangle (0 when degenerate).
std::array<float, 3> facet_normal(const Corners& corners);

/// Collects output in memory and hands it to the stream in large blocks; or appends it to a
/// string, which keeps it all (a chunk of records formatted on its own).
class OutputBuffer {
public:
    explicit OutputBuffer(std::ostream& out) : out_(&out), text_(&own_) { own_.reserve(kFlushSize + 256); }
    explicit OutputBuffer(std::string& into) : text_(&into) {}
    ~OutputBuffer() { flush(); }
    OutputBuffer(const OutputBuffer&) = delete;
    OutputBuffer& operator=(const OutputBuffer&) = delete;
    void flush() {
        if (!out_) return;
        out_->write(text_->data(), std::streamsize(text_->size()));
        text_->clear();
    }
    void text(std::string_view s) { text_->append(s), maybe_flush(); }
    /// The shortest decimal form that reads back as the same float.
    void number(float value) {
        char digits[32];
        const auto end = std::to_chars(digits, digits + sizeof digits, value).ptr;
        text_->append(digits, end), maybe_flush();
    }
    void number(std::uint64_t value) {
        char digits[32];
        const auto end = std::to_chars(digits, digits + sizeof digits, value).ptr;
        text_->append(digits, end), maybe_flush();
    }
    /// The value's bytes in little-endian order.
    template <class T>
    void binary(T value) {
        char raw[sizeof(T)];
        std::memcpy(raw, &value, sizeof(T));
        text_->append(raw, sizeof(T)), maybe_flush();
    }

private:
    static constexpr std::size_t kFlushSize = 1 << 20;
    void maybe_flush() {
        if (out_ && text_->size() >= kFlushSize) flush();
    }
    std::ostream* out_ = nullptr;  ///< none: the string given keeps everything
    std::string own_;
    std::string* text_;
};

/// Walks a text buffer token by token, counting lines for error messages.
class TextCursor {
public:
    TextCursor(const ByteView& bytes, std::size_t offset = 0, std::size_t line = 1)
        : data_(reinterpret_cast<const char*>(bytes.data())), pos_(offset), size_(bytes.size()), line_(line) {}
    /// The next whitespace-separated token on any line; empty at the end of the buffer.
    std::string_view token();
    /// The rest of the current line (without the newline), moving to the next line;
    /// returns false at the end of the buffer.
    bool line(std::string_view& text);
    std::size_t line_number() const { return line_; }
    std::size_t offset() const { return pos_; }
    bool at_end();  ///< only whitespace remains

private:
    const char* data_;
    std::size_t pos_, size_, line_;
};

/// Parses a finite float written in full (a leading '+' allowed); false otherwise.
bool parse_float(std::string_view text, float& value);
/// Parses a finite double written in full; false otherwise.
bool parse_double_value(std::string_view text, double& value);
/// Parses a whole signed integer; false otherwise.
bool parse_integer(std::string_view text, std::int64_t& value);

}  // namespace vdbmesh::detail
