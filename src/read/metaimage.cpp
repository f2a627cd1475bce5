// MetaImage .mhd/.mha headers (ITK MetaIO, https://itk.org/Wiki/ITK/MetaIO/Documentation):
// "Key = Value" lines; ElementDataFile is the last key and ends the header. Read here:
// NDims (2 or 3; a 2-D image is one slice, z = 1), DimSize, ElementType (MET_UCHAR, CHAR,
// USHORT, SHORT, UINT, INT, FLOAT, DOUBLE), ElementSpacing (or ElementSize),
// Offset/Position/Origin, TransformMatrix/Rotation/Orientation, BinaryDataByteOrderMSB/
// ElementByteOrderMSB, HeaderSize, CompressedData (zlib), CompressedDataSize, and
// ElementDataFile: LOCAL, a file name, a pattern "name%03d.raw first last step [filedim]",
// or "LIST [filedim]" followed by the file names.
//
// TransformMatrix convention (as ITK's MetaImageIO reads it): the NDims x NDims values are
// taken in groups of NDims, group i being the world direction of index axis i. Written as a
// row-major matrix, each ROW is one axis direction, i.e. the matrix is the transpose of the
// direction matrix whose columns are the axes. Offset is the world position of voxel (0,0,0).
//
// HeaderSize (as MetaIO applies it, also to LOCAL data): > 0 is the absolute offset of the
// samples in each data file; -1 puts them at the end of each file (the compressed size, from
// CompressedDataSize, is then needed for compressed data).

#include <string>

#include "formats.h"
#include "vdbmesh/parse_util.h"
#include "text_formats.h"
#include "text_header.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

const std::string kDataFile = "ElementDataFile";

/// The header's fields up to the ElementDataFile line, where the text after it starts, and
/// for "LIST" the words of the lines after it (the file names).
TextHeader parse_lines(std::string_view text, const std::filesystem::path& path) {
    TextHeader header{HeaderFields(path), 0, {}};
    HeaderLines lines(text);
    for (HeaderLine line; lines.next(line);) {
        const std::string_view content = trim(line.text);
        if (content.empty()) continue;
        const auto field = split_field(content, "=");
        if (!field || field->first.empty())
            throw FormatError(path.string(), HeaderLines::name(line), "a \"Key = Value\" line", shown(content));
        header.fields.add(field->first, field->second);
        if (to_lower(field->first) != to_lower(kDataFile)) continue;
        header.end = line.end;
        const auto words = split_words(field->second);
        if (!words.empty() && to_lower(words[0]) == "list")
            while (lines.next(line))
                for (std::string& word : split_words(line.text)) header.list_files.push_back(std::move(word));
        return header;
    }
    throw FormatError(path.string(), kDataFile, "a last line \"ElementDataFile = ...\"", "none (incomplete header)");
}

SampleType parse_element_type(const HeaderFields& fields) {
    const std::string_view value = fields.require("ElementType");
    const std::string name = to_lower(value);
    const std::pair<const char*, SampleType> kTypes[] = {
        {"met_uchar", SampleType::u8},  {"met_char", SampleType::i8},   {"met_ushort", SampleType::u16},
        {"met_short", SampleType::i16}, {"met_uint", SampleType::u32},  {"met_int", SampleType::i32},
        {"met_float", SampleType::f32}, {"met_double", SampleType::f64}};
    for (const auto& [known, type] : kTypes)
        if (name == known) return type;
    throw FormatError(fields.file().string(), "ElementType",
                      "MET_UCHAR, MET_CHAR, MET_USHORT, MET_SHORT, MET_UINT, MET_INT, MET_FLOAT or MET_DOUBLE",
                      shown(value));
}

void check_supported(const HeaderFields& fields) {
    const std::string file = fields.file().string();
    if (const auto type = fields.find("ObjectType"); type && to_lower(*type) != "image")
        throw FormatError(file, "ObjectType", "Image", shown(*type));
    if (const auto channels = fields.find("ElementNumberOfChannels");
        channels && parse_int(fields.file(), "ElementNumberOfChannels", *channels) != 1)
        throw FormatError(file, "ElementNumberOfChannels", "1 (scalar samples)", shown(*channels));
    if (const auto binary = fields.find("BinaryData"); binary && !parse_bool(fields.file(), "BinaryData", *binary))
        throw FormatError(file, "BinaryData", "True (ASCII samples are not supported)", shown(*binary));
}

/// Per-axis numbers of a key (or its synonyms), @a fallback for each axis when absent.
std::vector<double> axis_numbers(const HeaderFields& fields, const std::vector<std::string>& keys, std::size_t count,
                                 double fallback) {
    const auto found = fields.find_any(keys);
    if (!found) return std::vector<double>(count, fallback);
    return parse_double_list(fields.file(), found->first, found->second, count);
}

/// Sets spacing, orientation and origin; @a ndims is 2 or 3 (a 2-D image gets a unit z axis).
void set_geometry(const HeaderFields& fields, std::size_t ndims, VolumeHeader& header) {
    const auto spacing = axis_numbers(fields, {"ElementSpacing", "ElementSize"}, ndims, 1.0);
    const auto origin = axis_numbers(fields, {"Offset", "Position", "Origin"}, ndims, 0.0);
    std::vector<double> matrix(ndims * ndims, 0.0);
    for (std::size_t i = 0; i < ndims; ++i) matrix[i * ndims + i] = 1.0;
    const auto rotation = fields.find_any({"TransformMatrix", "Rotation", "Orientation"});
    if (rotation) matrix = parse_double_list(fields.file(), rotation->first, rotation->second, ndims * ndims);

    std::array<std::array<double, 3>, 3> axes{};
    axes[2][2] = 1.0;
    std::array<double, 3> world_origin{};
    for (std::size_t axis = 0; axis < ndims; ++axis) {
        world_origin[axis] = origin[axis];
        for (std::size_t row = 0; row < ndims; ++row) axes[axis][row] = matrix[axis * ndims + row] * spacing[axis];
    }
    set_axes(header, rotation ? rotation->first : "ElementSpacing", axes, world_origin);
}

void set_byte_order(const HeaderFields& fields, VolumeHeader& header) {
    const auto msb = fields.find_any({"BinaryDataByteOrderMSB", "ElementByteOrderMSB"});
    if (msb) {
        header.byte_order = parse_bool(fields.file(), msb->first, msb->second) ? ByteOrder::big : ByteOrder::little;
    } else if (sample_size(header.type) > 1) {
        header.warnings.push_back("no BinaryDataByteOrderMSB: little-endian assumed");
    }
}

/// "2D" or "2": the dimension of the samples each data file holds.
std::size_t parse_file_dimension(const std::filesystem::path& path, std::string_view word, std::size_t ndims) {
    std::string_view digits = word;
    if (!digits.empty() && (digits.back() == 'D' || digits.back() == 'd')) digits.remove_suffix(1);
    const std::int64_t dimension = parse_int(path, kDataFile, digits);
    if (dimension < 1 || dimension > static_cast<std::int64_t>(ndims))
        throw FormatError(path.string(), kDataFile, "a file dimension from 1 to " + std::to_string(ndims), shown(word));
    return static_cast<std::size_t>(dimension);
}

/// The data files: the header itself (LOCAL), a LIST, a pattern, or one file name.
DataFiles list_data_files(const TextHeader& meta, const std::filesystem::path& path,
                          const std::vector<std::int64_t>& sizes) {
    const std::size_t ndims = sizes.size();
    const std::string_view value = meta.fields.require(kDataFile);
    const auto words = split_words(value);
    if (words.empty()) throw FormatError(path.string(), kDataFile, "LOCAL, LIST, a file name or a pattern", "an empty value");
    const auto parse_dimension = [&](std::string_view word) { return parse_file_dimension(path, word, ndims); };
    if (auto listed = listed_data_files(meta, kDataFile, words, sizes, parse_dimension)) return *listed;
    DataFiles files;
    files.dimension = ndims;
    files.inside_header = to_lower(words[0]) == "local" && words.size() == 1;
    files.paths.push_back(files.inside_header ? path : data_path(path, value));
    return files;
}

/// How the samples are stored in each data file.
struct Storage {
    std::int64_t header_size = 0;      ///< HeaderSize: 0, an absolute offset, or -1 (at the end)
    bool compressed = false;           ///< CompressedData
    std::int64_t compressed_size = 0;  ///< CompressedDataSize (0: not given), used for a single file only
};

Storage parse_storage(const HeaderFields& fields, bool single_file) {
    const std::filesystem::path& header = fields.file();
    Storage storage;
    if (const auto value = fields.find("HeaderSize")) storage.header_size = parse_int(header, "HeaderSize", *value);
    if (storage.header_size < -1)
        throw FormatError(header.string(), "HeaderSize", "-1 or more", std::to_string(storage.header_size));
    if (const auto value = fields.find("CompressedData")) storage.compressed = parse_bool(header, "CompressedData", *value);
    if (const auto value = fields.find("CompressedDataSize"); value && storage.compressed && single_file) {
        storage.compressed_size = parse_int(header, "CompressedDataSize", *value);
        if (storage.compressed_size < 1) throw FormatError(header.string(), "CompressedDataSize", "> 0", shown(*value));
    }
    if (storage.header_size == -1 && storage.compressed && storage.compressed_size == 0)
        throw FormatError(header.string(), "CompressedDataSize",
                          "the compressed size of a single data file (HeaderSize -1 with compressed data)", "none");
    return storage;
}

/// The segment of one data file whose samples start at @a start unless HeaderSize says otherwise.
DataSegment data_segment(const std::filesystem::path& header, const Storage& storage, const std::filesystem::path& file,
                         std::uint64_t start, std::uint64_t bytes) {
    DataSegment segment;
    segment.path = file;
    segment.bytes = bytes;
    segment.compression = storage.compressed ? Compression::zlib : Compression::none;
    segment.file_offset = storage.header_size > 0 ? static_cast<std::uint64_t>(storage.header_size) : start;
    if (storage.header_size == -1) {
        const std::uint64_t stored = storage.compressed ? static_cast<std::uint64_t>(storage.compressed_size) : bytes;
        segment.file_offset = tail_offset(header, "HeaderSize", file, stored);
    }
    if (!storage.compressed) {
        check_plain_data_size(header, segment);
    } else if (storage.compressed_size > 0) {
        const std::uint64_t size = file_size_or_throw(file);
        const std::uint64_t available = size - std::min(size, segment.file_offset);
        if (available < static_cast<std::uint64_t>(storage.compressed_size))
            throw FormatError(header.string(), "CompressedDataSize",
                              "at most the " + std::to_string(available) + " bytes the data file holds after the header",
                              std::to_string(storage.compressed_size));
    }
    return segment;
}

}  // namespace

VolumeSource parse_metaimage_header(std::string_view text, const std::filesystem::path& path) {
    const TextHeader meta = parse_lines(text, path);
    const HeaderFields& fields = meta.fields;
    check_supported(fields);
    VolumeSource source;
    VolumeHeader& header = source.header;
    header.format = "metaimage";
    header.path = path;
    header.type = parse_element_type(fields);

    const std::string_view ndims_text = fields.require("NDims");
    const std::int64_t ndims = parse_int(path, "NDims", ndims_text);
    if (ndims != 2 && ndims != 3) throw FormatError(path.string(), "NDims", "2 or 3", shown(ndims_text));
    auto sizes = parse_int_list(path, "DimSize", fields.require("DimSize"), static_cast<std::size_t>(ndims));
    header.dims = {sizes[0], sizes[1], ndims == 3 ? sizes[2] : 1};
    check_dims(path, "DimSize", header.dims, sample_size(header.type));
    set_geometry(fields, static_cast<std::size_t>(ndims), header);
    set_byte_order(fields, header);

    const DataFiles files = list_data_files(meta, path, sizes);
    const std::uint64_t file_bytes =
        static_cast<std::uint64_t>(product(sizes, 0, files.dimension)) * sample_size(header.type);
    const Storage storage = parse_storage(fields, files.paths.size() == 1);
    for (const auto& file : files.paths) {
        if (!files.inside_header) require_data_file(path, kDataFile, file);
        source.segments.push_back(data_segment(path, storage, file, files.inside_header ? meta.end : 0, file_bytes));
    }
    return source;
}

VolumeSource read_metaimage(const std::filesystem::path& path) {
    const std::string text = read_header_text(path);
    VolumeSource source = parse_metaimage_header(text, path);
    if (source.segments.front().path == path && is_gzip(path))
        throw FormatError(path.string(), kDataFile, "LOCAL data in a plain (not gzipped) .mha", "a gzipped file");
    return source;
}

}  // namespace vdbmesh::detail
