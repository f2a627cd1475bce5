// OpenQVis .dat headers (the volume description of the OpenQVis renderer, Stegmaier et al.,
// openqvis.sourceforge.net, also read by Voreen): "Key: value" lines, spaces or tabs, '#'
// comment lines, unknown keys ignored. Keys used: ObjectFileName (the raw file, relative to
// the .dat), Resolution (x y z), SliceThickness (spacing), Format (UCHAR, USHORT or FLOAT:
// the three types the format lists), and Voreen's optional Unit. The format has no byte
// order key; files in practice are little-endian, which is assumed (with a warning).

#include <string>

#include "formats.h"
#include "vdbmesh/parse_util.h"
#include "text_formats.h"
#include "text_header.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

HeaderFields parse_fields(std::string_view text, const std::filesystem::path& path) {
    HeaderFields fields(path);
    HeaderLines lines(text);
    for (HeaderLine line; lines.next(line);) {
        const std::string_view content = trim(line.text);
        if (content.empty() || content.front() == '#') continue;
        const auto field = split_field(content, ":");
        if (!field || field->first.empty())
            throw FormatError(path.string(), HeaderLines::name(line), "a \"Key: value\" line", shown(content));
        fields.add(field->first, field->second);
    }
    return fields;
}

SampleType parse_format(const HeaderFields& fields) {
    const std::string_view value = fields.require("Format");
    const std::string name = to_lower(value);
    if (name == "uchar") return SampleType::u8;
    if (name == "ushort") return SampleType::u16;
    if (name == "float") return SampleType::f32;
    throw FormatError(fields.file().string(), "Format", "UCHAR, USHORT or FLOAT", shown(value));
}

std::array<double, 3> parse_spacing(const HeaderFields& fields, VolumeHeader& header) {
    const auto value = fields.find("SliceThickness");
    if (!value) {
        header.warnings.push_back("no SliceThickness: spacing 1 1 1 assumed");
        return {1, 1, 1};
    }
    const auto numbers = parse_double_list(fields.file(), "SliceThickness", *value, 3);
    for (double number : numbers)
        if (!(number > 0))
            throw FormatError(fields.file().string(), "SliceThickness", "three positive numbers", shown(*value));
    return {numbers[0], numbers[1], numbers[2]};
}

}  // namespace

VolumeSource parse_openqvis_header(std::string_view text, const std::filesystem::path& path) {
    const HeaderFields fields = parse_fields(text, path);
    VolumeSource source;
    VolumeHeader& header = source.header;
    header.format = "openqvis";
    header.path = path;
    header.type = parse_format(fields);
    const auto dims = parse_int_list(path, "Resolution", fields.require("Resolution"), 3);
    header.dims = {dims[0], dims[1], dims[2]};
    check_dims(path, "Resolution", header.dims, sample_size(header.type));
    header.spacing = parse_spacing(fields, header);
    header.index_to_world = axis_aligned_affine(header.spacing);
    if (const auto unit = fields.find("Unit")) header.units = std::string(*unit);
    header.byte_order = ByteOrder::little;
    if (sample_size(header.type) > 1)
        header.warnings.push_back("OpenQVis .dat has no byte order key: little-endian assumed");

    const std::string_view name = fields.require("ObjectFileName");
    if (name.empty()) throw FormatError(path.string(), "ObjectFileName", "a data file name", "an empty value");
    DataSegment segment;
    segment.path = data_path(path, name);
    segment.bytes = static_cast<std::uint64_t>(header.voxel_count()) * sample_size(header.type);
    segment.compression = Compression::none;  // the format has no compression
    require_data_file(path, "ObjectFileName", segment.path);
    check_plain_data_size(path, segment);
    source.segments.push_back(segment);
    return source;
}

VolumeSource read_openqvis(const std::filesystem::path& path) {
    return parse_openqvis_header(read_header_text(path), path);
}

}  // namespace vdbmesh::detail
