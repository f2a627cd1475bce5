// NRRD .nrrd/.nhdr headers (teem's "Definition of NRRD File Format",
// https://teem.sourceforge.net/nrrd/format.html): the magic NRRD0001 ... NRRD0005, then
// "field: value" lines, "key:=value" pairs (ignored) and '#' comments, up to an empty line
// after which attached data starts. Read here: dimension (3, or 4 with a first axis of size
// 1), type (every scalar type name NRRD allows except the 64-bit integers), sizes, endian,
// encoding (raw or gzip), spacings, or space directions + space origin, space / space
// dimension (coordinates stay in the file's space, noted in the warnings), space units or
// units, byte skip (-1: data at the end of a raw file), line skip, and data file: a name,
// a pattern "name%03d.raw first last step [filedim]", or LIST [filedim] with one file name
// per following line. Byte and line skips apply to every data file: lines are skipped in
// the file as stored, bytes after decompression (as the format defines them).

#include <algorithm>
#include <fstream>
#include <string>

#include "formats.h"
#include "vdbmesh/parse_util.h"
#include "text_formats.h"
#include "text_header.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

const std::string kDataFile = "data file";

bool is_magic(std::string_view line) {
    if (line == "NRRD00.01") return true;
    return line.size() == 8 && line.substr(0, 7) == "NRRD000" && line[7] >= '1' && line[7] <= '5';
}

/// The lines after "data file: LIST", up to an empty line or the end of the text.
void read_file_list(HeaderLines& lines, TextHeader& nrrd) {
    for (HeaderLine line; lines.next(line);) {
        const std::string_view name = trim(line.text);
        if (name.empty()) break;
        nrrd.list_files.emplace_back(name);
    }
}

/// The header's fields, where attached data would start (0: no empty line ended the
/// header), and for "data file: LIST" the file names on the lines after it.
TextHeader parse_lines(std::string_view text, const std::filesystem::path& path) {
    TextHeader nrrd{HeaderFields(path), 0, {}};
    HeaderLines lines(text);
    HeaderLine line;
    if (!lines.next(line) || !is_magic(trim(line.text)))
        throw FormatError(path.string(), "magic", "NRRD0001 ... NRRD0005 on the first line",
                          shown(line.number ? line.text : std::string_view{}));
    while (lines.next(line)) {
        const std::string_view content = trim(line.text);
        if (content.empty()) {
            nrrd.end = line.end;
            break;
        }
        if (content.front() == '#') continue;
        const std::size_t colon = content.find(':');
        if (colon == std::string_view::npos || colon == 0)
            throw FormatError(path.string(), HeaderLines::name(line), "a \"field: value\" line", shown(content));
        if (colon + 1 < content.size() && content[colon + 1] == '=') continue;  // key:=value, not ours
        std::string key = to_lower(trim(content.substr(0, colon)));
        if (key == "datafile") key = kDataFile;
        const std::string_view value = trim(content.substr(colon + 1));
        nrrd.fields.add(key, value);
        const auto words = split_words(value);
        if (key == kDataFile && !words.empty() && to_lower(words[0]) == "list") {
            read_file_list(lines, nrrd);
            break;
        }
    }
    return nrrd;
}

SampleType parse_type(const HeaderFields& fields) {
    const std::string_view value = fields.require("type");
    std::string name;
    for (const std::string& word : split_words(to_lower(value))) name += (name.empty() ? "" : " ") + word;
    const std::pair<SampleType, std::vector<const char*>> kNames[] = {
        {SampleType::u8, {"uchar", "unsigned char", "uint8", "uint8_t"}},
        {SampleType::i8, {"signed char", "int8", "int8_t"}},
        {SampleType::u16, {"ushort", "unsigned short", "unsigned short int", "uint16", "uint16_t"}},
        {SampleType::i16, {"short", "short int", "signed short", "signed short int", "int16", "int16_t"}},
        {SampleType::u32, {"uint", "unsigned int", "uint32", "uint32_t"}},
        {SampleType::i32, {"int", "signed int", "int32", "int32_t"}},
        {SampleType::f32, {"float"}},
        {SampleType::f64, {"double"}}};
    for (const auto& [type, names] : kNames)
        for (const char* known : names)
            if (name == known) return type;
    throw FormatError(fields.file().string(), "type",
                      "a NRRD scalar type of 8 to 32 bits (uchar, short, uint16, int32 ...), float or double "
                      "(64-bit integers and block are not supported)",
                      shown(value));
}

/// The sizes of all axes; a 4-D header must have a first axis of size 1.
std::vector<std::int64_t> parse_sizes(const HeaderFields& fields) {
    const std::filesystem::path& path = fields.file();
    const std::string_view dimension_text = fields.require("dimension");
    const std::int64_t dimension = parse_int(path, "dimension", dimension_text);
    if (dimension != 3 && dimension != 4)
        throw FormatError(path.string(), "dimension", "3 (or 4 with a first axis of size 1)", shown(dimension_text));
    const std::string_view sizes_text = fields.require("sizes");
    auto sizes = parse_int_list(path, "sizes", sizes_text, static_cast<std::size_t>(dimension));
    if (dimension == 4 && sizes[0] != 1)
        throw FormatError(path.string(), "sizes", "1 for the first of 4 axes (one value per voxel)", shown(sizes_text));
    return sizes;
}

/// "(1,0,0) none (0,1,0.5)": one optional 3-vector per axis ("none" for a non-spatial axis).
std::vector<std::optional<std::array<double, 3>>> parse_vectors(const std::filesystem::path& path,
                                                                const std::string& field, std::string_view text) {
    std::vector<std::optional<std::array<double, 3>>> vectors;
    text = trim(text);
    while (!text.empty()) {
        if (to_lower(text.substr(0, 4)) == "none") {
            vectors.emplace_back();
            text = trim(text.substr(4));
            continue;
        }
        const std::size_t close = text.find(')');
        if (text.front() != '(' || close == std::string_view::npos)
            throw FormatError(path.string(), field, "vectors like (1,0,0) or none", shown(text));
        const auto v = parse_double_list(path, field, text.substr(1, close - 1), 3, true);
        vectors.push_back(std::array<double, 3>{v[0], v[1], v[2]});
        text = trim(text.substr(close + 1));
    }
    return vectors;
}

void check_space(const HeaderFields& fields, VolumeHeader& header) {
    const std::string file = fields.file().string();
    if (const auto space = fields.find("space")) {
        const std::string name = to_lower(*space);
        const char* kSpaces[] = {"right-anterior-superior", "ras", "left-anterior-superior", "las",
                                 "left-posterior-superior", "lps", "scanner-xyz", "3d-right-handed", "3d-left-handed"};
        if (std::find(std::begin(kSpaces), std::end(kSpaces), name) == std::end(kSpaces))
            throw FormatError(file, "space",
                              "a 3-D space (RAS, LAS, LPS, scanner-xyz, 3D-right-handed, 3D-left-handed)", shown(*space));
        header.warnings.push_back("world coordinates are in the file's space \"" + std::string(*space) +
                                  "\" (kept as they are)");
    }
    if (const auto dimension = fields.find("space dimension");
        dimension && parse_int(fields.file(), "space dimension", *dimension) != 3)
        throw FormatError(file, "space dimension", "3", shown(*dimension));
}

/// The world step of each spatial axis, from "space directions" or else "spacings".
std::array<std::array<double, 3>, 3> axis_vectors(const HeaderFields& fields, std::size_t first_axis,
                                                  std::size_t dimension, VolumeHeader& header) {
    const std::filesystem::path& path = fields.file();
    std::array<std::array<double, 3>, 3> axes{};
    if (const auto directions = fields.find("space directions")) {
        const auto vectors = parse_vectors(path, "space directions", *directions);
        if (vectors.size() != dimension)
            throw FormatError(path.string(), "space directions", std::to_string(dimension) + " entries", shown(*directions));
        for (std::size_t axis = 0; axis < 3; ++axis) {
            if (!vectors[first_axis + axis])
                throw FormatError(path.string(), "space directions", "a vector for each spatial axis",
                                  "none for axis " + std::to_string(first_axis + axis));
            axes[axis] = *vectors[first_axis + axis];
        }
        if (fields.find("spacings")) header.warnings.push_back("spacings ignored: space directions given");
        return axes;
    }
    const auto spacings = fields.find("spacings");
    if (!spacings) header.warnings.push_back("no spacings or space directions: spacing 1 1 1 assumed");
    const auto words = spacings ? split_words(*spacings) : std::vector<std::string>(dimension, "1");
    if (words.size() != dimension)
        throw FormatError(path.string(), "spacings", std::to_string(dimension) + " numbers", shown(*spacings));
    for (std::size_t axis = 0; axis < 3; ++axis) axes[axis][axis] = parse_double(path, "spacings", words[first_axis + axis]);
    return axes;
}

/// "mm" when every spatial axis has that unit ("space units", else "units"), else empty.
std::string common_unit(const HeaderFields& fields, std::size_t first_axis) {
    const auto value = fields.find_any({"space units", "units"});
    if (!value) return {};
    std::vector<std::string> units;
    std::string_view text = value->second;
    for (std::size_t open = text.find('"'); open != std::string_view::npos; open = text.find('"')) {
        const std::size_t close = text.find('"', open + 1);
        if (close == std::string_view::npos) break;
        units.emplace_back(text.substr(open + 1, close - open - 1));
        text.remove_prefix(close + 1);
    }
    if (value->first == "units" && units.size() > first_axis) units.erase(units.begin(), units.begin() + first_axis);
    if (units.size() != 3 || units[0].empty() || units[1] != units[0] || units[2] != units[0]) return {};
    return units[0];
}

void set_geometry(const HeaderFields& fields, std::size_t dimension, VolumeHeader& header) {
    const std::size_t first_axis = dimension - 3;
    check_space(fields, header);
    const auto axes = axis_vectors(fields, first_axis, dimension, header);
    std::array<double, 3> origin{};
    if (const auto text = fields.find("space origin")) {
        const auto vectors = parse_vectors(fields.file(), "space origin", *text);
        if (vectors.size() != 1 || !vectors[0])
            throw FormatError(fields.file().string(), "space origin", "one vector like (0,0,0)", shown(*text));
        origin = *vectors[0];
    }
    set_axes(header, fields.find("space directions") ? "space directions" : "spacings", axes, origin);
    header.units = common_unit(fields, first_axis);
}

/// How the samples are stored in each data file.
struct Storage {
    bool gzip = false;
    std::int64_t byte_skip = 0;
    std::int64_t line_skip = 0;
};

Storage parse_storage(const HeaderFields& fields, VolumeHeader& header) {
    const std::filesystem::path& path = fields.file();
    Storage storage;
    const std::string_view encoding = fields.require("encoding");
    const std::string name = to_lower(encoding);
    if (name != "raw" && name != "gzip" && name != "gz")
        throw FormatError(path.string(), "encoding", "raw or gzip (ascii, hex and bzip2 are not supported)", shown(encoding));
    storage.gzip = name != "raw";
    const auto endian = fields.find("endian");
    if (!endian && sample_size(header.type) > 1)
        throw FormatError(path.string(), "endian", "an \"endian\" line (little or big) for multi-byte samples", "none");
    if (endian) {
        const std::string order = to_lower(*endian);
        if (order != "little" && order != "big") throw FormatError(path.string(), "endian", "little or big", shown(*endian));
        header.byte_order = order == "big" ? ByteOrder::big : ByteOrder::little;
    }
    if (const auto value = fields.find("byte skip")) storage.byte_skip = parse_int(path, "byte skip", *value);
    if (storage.byte_skip < -1 || (storage.byte_skip == -1 && storage.gzip))
        throw FormatError(path.string(), "byte skip", "0 or more (-1 only with raw encoding)", std::to_string(storage.byte_skip));
    if (const auto value = fields.find("line skip")) storage.line_skip = parse_int(path, "line skip", *value);
    if (storage.line_skip < 0) throw FormatError(path.string(), "line skip", "0 or more", std::to_string(storage.line_skip));
    return storage;
}

std::size_t parse_file_dimension(const std::filesystem::path& path, std::string_view word, std::size_t dimension) {
    const std::int64_t value = parse_int(path, kDataFile, word);
    if (value < 1 || value > static_cast<std::int64_t>(dimension))
        throw FormatError(path.string(), kDataFile, "a file dimension from 1 to " + std::to_string(dimension), shown(word));
    return static_cast<std::size_t>(value);
}

/// The data files: attached data, a LIST, a pattern, or one file name.
DataFiles list_data_files(const TextHeader& nrrd, const std::vector<std::int64_t>& sizes) {
    const std::filesystem::path& path = nrrd.fields.file();
    const std::size_t dimension = sizes.size();
    DataFiles files;
    files.dimension = dimension;
    const auto value = nrrd.fields.find(kDataFile);
    if (!value) {
        if (nrrd.end == 0)
            throw FormatError(path.string(), kDataFile, "a \"data file\" line, or data after the empty line ending the header",
                              "neither");
        files.inside_header = true;
        files.paths.push_back(path);
        return files;
    }
    const auto parse_dimension = [&](std::string_view word) { return parse_file_dimension(path, word, dimension); };
    if (auto listed = listed_data_files(nrrd, kDataFile, split_words(*value), sizes, parse_dimension)) return *listed;
    if (value->empty()) throw FormatError(path.string(), kDataFile, "a file name, a pattern or LIST", "an empty value");
    files.paths.push_back(data_path(path, *value));
    return files;
}

DataSegment data_segment(const std::filesystem::path& header, const Storage& storage, const std::filesystem::path& file,
                         std::uint64_t start, std::uint64_t bytes, const LineSkipper& skip_lines) {
    DataSegment segment;
    segment.path = file;
    segment.bytes = bytes;
    if (storage.line_skip > 0 && storage.byte_skip != -1) start += skip_lines(file, start, storage.line_skip);
    if (storage.gzip) {
        segment.file_offset = start;
        segment.offset = static_cast<std::uint64_t>(storage.byte_skip);
        return segment;
    }
    segment.compression = Compression::none;
    segment.file_offset = storage.byte_skip == -1 ? tail_offset(header, "byte skip", file, bytes)
                                                  : start + static_cast<std::uint64_t>(storage.byte_skip);
    check_plain_data_size(header, segment);
    return segment;
}

/// Reads the data file to find where its first @a lines lines end.
std::uint64_t skip_lines_in_file(const std::filesystem::path& file, std::uint64_t offset, std::int64_t lines) {
    std::ifstream in(file, std::ios::binary);
    in.seekg(static_cast<std::streamoff>(offset));
    std::uint64_t bytes = 0;
    for (std::int64_t line = 0; line < lines; ++line) {
        for (int c = in.get(); c != '\n'; c = in.get(), ++bytes)
            if (c == std::char_traits<char>::eof())
                throw FormatError(file.string(), "line skip", std::to_string(lines) + " lines before the data",
                                  "only " + std::to_string(line));
        ++bytes;
    }
    return bytes;
}

}  // namespace

VolumeSource parse_nrrd_header(std::string_view text, const std::filesystem::path& path, const LineSkipper& skip_lines) {
    const TextHeader nrrd = parse_lines(text, path);
    VolumeSource source;
    VolumeHeader& header = source.header;
    header.format = "nrrd";
    header.path = path;
    header.type = parse_type(nrrd.fields);
    const auto sizes = parse_sizes(nrrd.fields);
    const std::size_t first_axis = sizes.size() - 3;
    header.dims = {sizes[first_axis], sizes[first_axis + 1], sizes[first_axis + 2]};
    check_dims(path, "sizes", header.dims, sample_size(header.type));
    set_geometry(nrrd.fields, sizes.size(), header);
    const Storage storage = parse_storage(nrrd.fields, header);

    const DataFiles files = list_data_files(nrrd, sizes);
    const std::uint64_t file_bytes =
        static_cast<std::uint64_t>(product(sizes, 0, files.dimension)) * sample_size(header.type);
    for (const auto& file : files.paths) {
        if (!files.inside_header) require_data_file(path, kDataFile, file);
        source.segments.push_back(data_segment(path, storage, file, files.inside_header ? nrrd.end : 0, file_bytes, skip_lines));
    }
    return source;
}

VolumeSource read_nrrd(const std::filesystem::path& path) {
    const std::string text = read_header_text(path);
    VolumeSource source = parse_nrrd_header(text, path, skip_lines_in_file);
    if (source.segments.front().path == path && is_gzip(path))
        throw FormatError(path.string(), "data", "attached data in a plain (not gzipped) .nrrd", "a gzipped file");
    return source;
}

}  // namespace vdbmesh::detail
