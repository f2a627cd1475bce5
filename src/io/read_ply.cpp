// PLY reader (G. Turk, "The PLY Polygon File Format", 1994; the type names of
// Paul Bourke's description, plus the sized aliases int8 ... float64). Reads ascii,
// binary_little_endian and binary_big_endian; vertex x, y, z of any scalar type; the face
// list "vertex_indices" (or "vertex_index") with any integer count and index types,
// triangulated as fans; every other element and property is read past and dropped.
// Element counts are checked against the bytes left before anything is allocated.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "io/mesh_io_detail.h"
#include "vdbmesh/parse_util.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {
namespace {

constexpr std::size_t kMaxHeaderBytes = 1 << 20;

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };
enum class Encoding { kAscii, kLittleEndian, kBigEndian };

std::optional<PlyType> type_named(std::string_view name) {
    static const std::pair<const char*, PlyType> kNames[] = {
        {"char", PlyType::kInt8},     {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
        {"uint8", PlyType::kUint8},   {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
        {"ushort", PlyType::kUint16}, {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
        {"int32", PlyType::kInt32},   {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
        {"float", PlyType::kFloat32}, {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
        {"float64", PlyType::kFloat64}};
    for (const auto& [text, type] : kNames) {
        if (name == text) return type;
    }
    return std::nullopt;
}

std::size_t size_of(PlyType type) {
    switch (type) {
        case PlyType::kInt8: case PlyType::kUint8: return 1;
        case PlyType::kInt16: case PlyType::kUint16: return 2;
        case PlyType::kInt32: case PlyType::kUint32: case PlyType::kFloat32: return 4;
        case PlyType::kFloat64: return 8;
    }
    return 1;
}

bool is_integer(PlyType type) { return type != PlyType::kFloat32 && type != PlyType::kFloat64; }

struct Property {
    std::string name;
    PlyType type = PlyType::kFloat32;
    bool is_list = false;
    PlyType count_type = PlyType::kUint8;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
};

struct Header {
    Encoding encoding = Encoding::kAscii;
    std::vector<Element> elements;
    std::size_t body_offset = 0;
    std::size_t body_line = 1;  ///< line number where an ASCII body starts
};

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& field, const std::string& expected,
                       const std::string& actual) {
    throw FormatError(file.string(), field, expected, actual);
}

Property parse_property(const std::filesystem::path& file, const std::vector<std::string>& words, std::size_t line) {
    const std::string field = "header line " + std::to_string(line) + ": property";
    Property property;
    if (words.size() == 5 && words[1] == "list") {
        const auto count_type = type_named(words[2]), type = type_named(words[3]);
        if (!count_type || !is_integer(*count_type)) fail(file, field, "an integer list count type", "'" + words[2] + "'");
        if (!type) fail(file, field, "a PLY scalar type", "'" + words[3] + "'");
        property = {words[4], *type, true, *count_type};
    } else if (words.size() == 3) {
        const auto type = type_named(words[1]);
        if (!type) fail(file, field, "a PLY scalar type", "'" + words[1] + "'");
        property = {words[2], *type, false, PlyType::kUint8};
    } else {
        fail(file, field, "'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'", std::to_string(words.size()) + " words");
    }
    return property;
}

Header parse_header(const std::filesystem::path& file, const ByteView& bytes) {
    TextCursor cursor(bytes);
    std::string_view text;
    if (!cursor.line(text) || trim(text) != "ply") fail(file, "magic", "'ply'", "'" + std::string(text.substr(0, 16)) + "'");
    Header header;
    bool has_format = false;
    while (true) {
        const std::size_t line_number = cursor.line_number();
        if (!cursor.line(text)) fail(file, "header", "'end_header'", "end of file");
        if (cursor.offset() > kMaxHeaderBytes) fail(file, "header", "'end_header' within 1 MiB", "none");
        const std::vector<std::string> words = split_words(text);
        if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
        const std::string field = "header line " + std::to_string(line_number);
        if (words[0] == "end_header") break;
        if (words[0] == "format") {
            if (words.size() != 3) fail(file, field + ": format", "'format ENCODING 1.0'", std::string(text));
            if (words[1] == "ascii") header.encoding = Encoding::kAscii;
            else if (words[1] == "binary_little_endian") header.encoding = Encoding::kLittleEndian;
            else if (words[1] == "binary_big_endian") header.encoding = Encoding::kBigEndian;
            else fail(file, field + ": format", "ascii, binary_little_endian or binary_big_endian", "'" + words[1] + "'");
            has_format = true;
        } else if (words[0] == "element") {
            if (words.size() != 3) fail(file, field + ": element", "'element NAME COUNT'", std::string(text));
            const std::int64_t count = parse_int(file, field + ": element " + words[1] + " count", words[2]);
            if (count < 0) fail(file, field + ": element " + words[1] + " count", ">= 0", words[2]);
            header.elements.push_back({words[1], std::uint64_t(count), {}});
        } else if (words[0] == "property") {
            if (header.elements.empty()) fail(file, field, "'element' before 'property'", "'property'");
            header.elements.back().properties.push_back(parse_property(file, words, line_number));
        } else {
            fail(file, field, "a PLY header keyword", "'" + words[0] + "'");
        }
    }
    if (!has_format) fail(file, "format", "a 'format' line", "none");
    header.body_line = cursor.line_number();
    header.body_offset = cursor.offset();
    return header;
}

/// Reads values of an element body, binary or ASCII.
class ValueReader {
public:
    ValueReader(const std::filesystem::path& file, const ByteView& bytes, const Header& header)
        : file_(file), bytes_(bytes), encoding_(header.encoding), pos_(header.body_offset),
          text_(bytes, header.body_offset, header.body_line) {}

    double real(PlyType type, const char* field) {
        if (encoding_ == Encoding::kAscii) {
            const std::string_view word = text_.token();
            if (type == PlyType::kFloat32) {
                float value = 0;
                if (parse_float(word, value)) return value;
            } else {
                double value = 0;
                if (parse_double_value(word, value)) return value;
            }
            bad_text(field, "a finite number", word);
        }
        return binary(type, field);
    }

    std::int64_t integer(PlyType type, const char* field) {
        if (encoding_ == Encoding::kAscii) {
            const std::string_view word = text_.token();
            std::int64_t value = 0;
            if (parse_integer(word, value)) return value;
            bad_text(field, "an integer", word);
        }
        const double value = binary(type, field);
        if (!is_integer(type) && value != std::floor(value)) fail(file_, field, "an integer value", std::to_string(value));
        return std::int64_t(value);
    }

    void skip(const Property& property) {
        const std::int64_t count = property.is_list ? integer(property.count_type, "list count") : 1;
        if (count < 0) fail(file_, "list count of " + property.name, ">= 0", std::to_string(count));
        for (std::int64_t k = 0; k < count; ++k) real(property.type, "skipped property");
    }

    /// Checks that nothing but (ASCII) whitespace follows the last element.
    void expect_end() {
        if (encoding_ == Encoding::kAscii) {
            if (!text_.at_end()) bad_text("after the last element", "end of file", text_.token());
        } else if (pos_ != bytes_.size()) {
            fail(file_, "file size", std::to_string(pos_) + " bytes (from the header's element counts)",
                 std::to_string(bytes_.size()) + " bytes");
        }
    }

    /// Fewest bytes one value can take.
    std::size_t min_bytes(PlyType type) const { return encoding_ == Encoding::kAscii ? 2 : size_of(type); }
    std::size_t remaining() const { return bytes_.size() - std::min(bytes_.size(), pos_); }
    /// Between records: nothing before the current place is read again.
    void record_done() { bytes_.done_before(encoding_ == Encoding::kAscii ? text_.offset() : pos_); }

private:
    double binary(PlyType type, const char* field) {
        const std::size_t size = size_of(type);
        if (pos_ + size > bytes_.size()) fail(file_, field, "more data", "end of file (truncated body)");
        unsigned char raw[8];
        std::memcpy(raw, bytes_.data() + pos_, size);
        pos_ += size;
        if (encoding_ == Encoding::kBigEndian) std::reverse(raw, raw + size);
        switch (type) {
            case PlyType::kInt8: return double(std::int8_t(raw[0]));
            case PlyType::kUint8: return double(raw[0]);
            case PlyType::kInt16: return load<std::int16_t>(raw);
            case PlyType::kUint16: return load<std::uint16_t>(raw);
            case PlyType::kInt32: return load<std::int32_t>(raw);
            case PlyType::kUint32: return load<std::uint32_t>(raw);
            case PlyType::kFloat32: return load<float>(raw);
            case PlyType::kFloat64: return load<double>(raw);
        }
        return 0;
    }

    template <class T>
    static double load(const unsigned char* raw) {
        T value;
        std::memcpy(&value, raw, sizeof(T));
        return double(value);
    }

    [[noreturn]] void bad_text(const std::string& field, const std::string& expected, std::string_view word) {
        fail(file_, "line " + std::to_string(text_.line_number()) + ": " + field, expected,
             word.empty() ? "end of file" : "'" + std::string(word) + "'");
    }

    const std::filesystem::path& file_;
    const ByteView& bytes_;
    Encoding encoding_;
    std::size_t pos_;
    TextCursor text_;
};

/// Checks that @a element's count fits in the bytes left (each value takes at least its
/// minimum size) before anything is allocated for it.
std::uint64_t most_elements(const Element& element, const ValueReader& reader) {
    std::size_t per_element = 0;
    for (const Property& p : element.properties) per_element += reader.min_bytes(p.is_list ? p.count_type : p.type);
    // + 1: the last ASCII value needs no separator after it.
    return per_element > 0 ? (reader.remaining() + 1) / per_element : element.count;
}

void check_count(const std::filesystem::path& file, const Element& element, const ValueReader& reader) {
    const std::uint64_t most = most_elements(element, reader);
    if (element.count > most) {
        fail(file, "element " + element.name + " count", "at most " + std::to_string(most) + " (bytes left in the file)",
             std::to_string(element.count));
    }
    if (element.name == "vertex" && element.count > std::numeric_limits<std::uint32_t>::max()) {
        fail(file, "element vertex count", "at most 2^32 - 1", std::to_string(element.count));
    }
}

void read_vertices(const std::filesystem::path& file, const Element& element, ValueReader& reader, MeshRecordVisitor& visitor) {
    int axis_of[3] = {-1, -1, -1};
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const Property& property = element.properties[p];
        for (int k = 0; k < 3; ++k) {
            if (property.name == std::string(1, char('x' + k)) && !property.is_list) axis_of[k] = int(p);
        }
    }
    for (int k = 0; k < 3; ++k) {
        if (axis_of[k] < 0) fail(file, "element vertex", std::string("a scalar property ") + char('x' + k), "none");
    }
    for (std::uint64_t v = 0; v < element.count; ++v) {
        std::array<float, 3> vertex{};
        for (std::size_t p = 0; p < element.properties.size(); ++p) {
            const Property& property = element.properties[p];
            const int axis = int(std::find(axis_of, axis_of + 3, int(p)) - axis_of);
            if (axis == 3) {
                reader.skip(property);
                continue;
            }
            vertex[axis] = float(reader.real(property.type, "vertex coordinate"));
            if (!std::isfinite(vertex[axis])) fail(file, "vertex coordinate", "a finite float", "an overflow");
        }
        visitor.vertex(vertex);
        reader.record_done();
    }
}

void read_faces(const std::filesystem::path& file, const Element& element, std::uint64_t vertices, ValueReader& reader,
                MeshRecordVisitor& visitor) {
    const auto list = std::find_if(element.properties.begin(), element.properties.end(), [](const Property& p) {
        return p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index");
    });
    if (list == element.properties.end()) fail(file, "element face", "a list property vertex_indices", "none");
    if (!is_integer(list->type)) fail(file, "face vertex_indices", "an integer index type", "a floating-point type");
    std::vector<std::uint32_t> polygon;
    for (std::uint64_t f = 0; f < element.count; ++f) {
        for (const Property& property : element.properties) {
            if (&property != &*list) {
                reader.skip(property);
                continue;
            }
            const std::int64_t count = reader.integer(property.count_type, "face vertex count");
            if (count < 3) fail(file, "face " + std::to_string(f) + " vertex count", ">= 3", std::to_string(count));
            polygon.clear();
            for (std::int64_t k = 0; k < count; ++k) {
                const std::int64_t index = reader.integer(property.type, "face vertex index");
                if (index < 0 || std::uint64_t(index) >= vertices) {
                    fail(file, "face " + std::to_string(f) + " vertex index", "0 .. " + std::to_string(std::int64_t(vertices) - 1),
                         std::to_string(index));
                }
                polygon.push_back(std::uint32_t(index));
            }
            for (std::size_t k = 1; k + 1 < polygon.size(); ++k) visitor.triangle({polygon[0], polygon[k], polygon[k + 1]});
        }
        reader.record_done();
    }
}

/// The face count the header announces, at most what the bytes left can hold (a hint for
/// the visitor's memory: the count itself is checked when the faces come).
std::uint64_t announced_faces(const Header& header, const ValueReader& reader) {
    for (const Element& element : header.elements) {
        if (element.name == "face") return std::min(element.count, most_elements(element, reader));
    }
    return 0;
}

}  // namespace

void read_ply_records(const std::filesystem::path& file, const ByteView& bytes, MeshRecordVisitor& visitor) {
    const Header header = parse_header(file, bytes);
    ValueReader reader(file, bytes, header);
    std::uint64_t vertices = 0;
    bool has_vertices = false;
    for (const Element& element : header.elements) {
        check_count(file, element, reader);
        if (element.name == "vertex") {
            if (has_vertices) fail(file, "element vertex", "one vertex element", "two");
            visitor.announced(element.count, announced_faces(header, reader));
            read_vertices(file, element, reader, visitor);
            vertices = element.count;
            has_vertices = true;
        } else if (element.name == "face") {
            if (!has_vertices) fail(file, "element face", "after element vertex", "before it");
            read_faces(file, element, vertices, reader, visitor);
        } else if (!element.properties.empty()) {  // an element without properties takes no bytes, whatever its count
            for (std::uint64_t i = 0; i < element.count; ++i) {
                for (const Property& property : element.properties) reader.skip(property);
                reader.record_done();
            }
        }
    }
    if (!has_vertices) fail(file, "element vertex", "a vertex element", "none");
    reader.expect_end();
}

Mesh read_ply(const std::filesystem::path& file, const Bytes& bytes) {
    MeshBuilder builder;
    read_ply_records(file, bytes, builder);
    return std::move(builder.mesh);
}

}  // namespace vdbmesh::detail
