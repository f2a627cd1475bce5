// STL reader (3D Systems' StereoLithography Interface Specification, 1989). Binary and
// ASCII are told apart by size: a binary file is exactly 84 + 50 n bytes for the n in its
// header, while many binary files also begin with "solid". Corners are welded only when
// their coordinates are bit-identical (a sort of the corners by their bits, vertices numbered
// in order of first appearance); nothing else is merged or repaired.
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>

#include "io/mesh_io_detail.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {
namespace {

constexpr std::size_t kHeaderBytes = 84, kFacetBytes = 50;
using Corner = std::array<float, 3>;

/// Welds corners (three per triangle) with bit-identical coordinates.
Mesh weld(const std::vector<Corner>& corners) {
    struct Key {
        std::uint32_t x, y, z, corner;
        bool operator<(const Key& o) const { return std::tie(x, y, z, corner) < std::tie(o.x, o.y, o.z, o.corner); }
    };
    const std::size_t n = corners.size();
    std::vector<Key> keys(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
        std::memcpy(&keys[i], corners[i].data(), 3 * sizeof(float));
        keys[i].corner = std::uint32_t(i);
    });
    tbb::parallel_sort(keys.begin(), keys.end());
    // The first corner of each group (smallest index) represents it.
    std::vector<std::uint32_t> representative(n);
    for (std::size_t i = 0; i < n; ++i) {
        const bool same = i > 0 && keys[i].x == keys[i - 1].x && keys[i].y == keys[i - 1].y && keys[i].z == keys[i - 1].z;
        representative[keys[i].corner] = same ? representative[keys[i - 1].corner] : keys[i].corner;
    }
    Mesh mesh;
    mesh.triangles.resize(n / 3);
    std::vector<std::uint32_t> vertex_of(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (representative[i] == i) {
            vertex_of[i] = std::uint32_t(mesh.vertices.size());
            mesh.vertices.push_back(corners[i]);
        } else {
            vertex_of[i] = vertex_of[representative[i]];
        }
        mesh.triangles[i / 3][i % 3] = vertex_of[i];
    }
    return mesh;
}

/// read_stl()'s visitor: the facets' corners, welded at the end.
struct CornerCollector final : MeshRecordVisitor {
    std::vector<Corner> corners;
    void announced(std::uint64_t, std::uint64_t facets) override { corners.reserve(3 * facets); }
    void vertex(const Corner&) override {}
    void triangle(const std::array<std::uint32_t, 3>&) override {}
    void facet(const Corners& facet) override { corners.insert(corners.end(), facet.begin(), facet.end()); }
};

void read_binary(const std::filesystem::path& file, const ByteView& bytes, std::uint32_t count, MeshRecordVisitor& visitor) {
    visitor.announced(0, count);
    for (std::size_t f = 0; f < count; ++f) {
        const unsigned char* record = bytes.data() + kHeaderBytes + f * kFacetBytes + 12;  // skip the normal
        Corners corners;
        for (int c = 0; c < 3; ++c) std::memcpy(corners[c].data(), record + 12 * c, 12);
        for (const Corner& corner : corners) {
            for (const float value : corner) {
                if (!std::isfinite(value)) {
                    throw FormatError(file.string(), "facet " + std::to_string(f) + " vertex", "finite coordinates", std::to_string(value));
                }
            }
        }
        visitor.facet(corners);
        bytes.done_before(kHeaderBytes + (f + 1) * kFacetBytes);
    }
}

void expect_keyword(const std::filesystem::path& file, TextCursor& cursor, std::string_view keyword) {
    const std::string_view got = cursor.token();
    if (got != keyword) {
        throw FormatError(file.string(), "line " + std::to_string(cursor.line_number()), "'" + std::string(keyword) + "'",
                          got.empty() ? "end of file" : "'" + std::string(got) + "'");
    }
}

float read_number(const std::filesystem::path& file, TextCursor& cursor, const char* field) {
    const std::string_view text = cursor.token();
    float value = 0;
    if (!parse_float(text, value)) {
        throw FormatError(file.string(), "line " + std::to_string(cursor.line_number()) + ": " + field,
                          "a finite number", text.empty() ? "end of file" : "'" + std::string(text) + "'");
    }
    return value;
}

void read_ascii(const std::filesystem::path& file, const ByteView& bytes, MeshRecordVisitor& visitor) {
    TextCursor cursor(bytes);
    std::uint64_t facets = 0;
    std::string_view word = cursor.token();
    while (word == "solid") {
        std::string_view name;
        cursor.line(name);  // the solid's name
        for (word = cursor.token(); word == "facet"; word = cursor.token()) {
            expect_keyword(file, cursor, "normal");
            for (int k = 0; k < 3; ++k) read_number(file, cursor, "facet normal");
            expect_keyword(file, cursor, "outer");
            expect_keyword(file, cursor, "loop");
            Corners corners;
            for (Corner& corner : corners) {
                expect_keyword(file, cursor, "vertex");
                for (float& value : corner) value = read_number(file, cursor, "vertex");
            }
            expect_keyword(file, cursor, "endloop");
            expect_keyword(file, cursor, "endfacet");
            visitor.facet(corners);
            ++facets;
            bytes.done_before(cursor.offset());
        }
        if (word != "endsolid") {
            throw FormatError(file.string(), "line " + std::to_string(cursor.line_number()), "'facet' or 'endsolid'",
                              word.empty() ? "end of file" : "'" + std::string(word) + "'");
        }
        cursor.line(name);
        word = cursor.token();
    }
    if (!word.empty()) {
        throw FormatError(file.string(), "line " + std::to_string(cursor.line_number()), "'solid' or end of file",
                          "'" + std::string(word) + "'");
    }
    if (facets > std::numeric_limits<std::uint32_t>::max()) {
        throw FormatError(file.string(), "facet count", "at most 2^32 - 1", std::to_string(facets));
    }
}

/// "solid" after optional whitespace, and no control bytes in the first kilobyte.
bool looks_like_ascii(const ByteView& bytes) {
    std::size_t i = 0;
    while (i < bytes.size() && (bytes[i] == ' ' || bytes[i] == '\t' || bytes[i] == '\r' || bytes[i] == '\n')) ++i;
    if (bytes.size() - i < 5 || std::memcmp(bytes.data() + i, "solid", 5) != 0) return false;
    for (std::size_t k = 0; k < std::min<std::size_t>(bytes.size(), 1024); ++k) {
        const unsigned char c = bytes[k];
        if (c < 9 || (c > 13 && c < 32)) return false;
    }
    return true;
}

}  // namespace

void read_stl_records(const std::filesystem::path& file, const ByteView& bytes, MeshRecordVisitor& visitor) {
    if (bytes.size() >= kHeaderBytes) {
        std::uint32_t count = 0;
        std::memcpy(&count, bytes.data() + 80, 4);
        if (bytes.size() == kHeaderBytes + kFacetBytes * std::uint64_t(count)) return read_binary(file, bytes, count, visitor);
        if (!looks_like_ascii(bytes)) {
            throw FormatError(file.string(), "file size", "84 + 50 x " + std::to_string(count) + " facets = " +
                                  std::to_string(kHeaderBytes + kFacetBytes * std::uint64_t(count)) + " bytes",
                              std::to_string(bytes.size()) + " bytes");
        }
    } else if (!looks_like_ascii(bytes)) {
        throw FormatError(file.string(), "file size", "at least 84 bytes (binary STL) or 'solid' (ASCII STL)",
                          std::to_string(bytes.size()) + " bytes");
    }
    read_ascii(file, bytes, visitor);
}

Mesh read_stl(const std::filesystem::path& file, const Bytes& bytes) {
    CornerCollector collector;
    read_stl_records(file, bytes, collector);
    return weld(collector.corners);
}

}  // namespace vdbmesh::detail
