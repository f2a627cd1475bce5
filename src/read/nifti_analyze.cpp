// NIfTI-1 (.nii, .nii.gz, .hdr/.img pairs) and Analyze 7.5 (.hdr/.img pairs): finds the
// header and data files, parses the header (nifti_header.cpp, NIfTI-1 standard and Mayo's
// Analyze 7.5 format) and says where the samples are. Either file of a pair may be gzipped.

#include <cctype>
#include <optional>

#include "formats.h"
#include "nifti_header.h"
#include "vdbmesh/parse_util.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

/// "a.img.gz" -> {"a", ".img"} (extension lower-cased); the ".gz" is looked through.
std::pair<std::string, std::string> split_name(const std::filesystem::path& path) {
    std::filesystem::path name = path.filename();
    if (to_lower(name.extension().string()) == ".gz") name = name.stem();
    return {name.stem().string(), to_lower(name.extension().string())};
}

/// The file beside @a path with extension @a ext (".hdr" or ".img"), plain or gzipped, in
/// lower or upper case; nothing when there is none.
std::optional<std::filesystem::path> find_partner(const std::filesystem::path& path, const std::string& ext) {
    const std::string stem = split_name(path).first;
    std::string upper = ext;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    for (const std::string& candidate : {stem + ext, stem + ext + ".gz", stem + upper, stem + upper + ".GZ"}) {
        const std::filesystem::path partner = path.parent_path() / candidate;
        std::error_code ec;
        if (std::filesystem::is_regular_file(partner, ec)) return partner;
    }
    return std::nullopt;
}

std::filesystem::path require_partner(const std::filesystem::path& path, const std::string& ext,
                                      const std::string& field) {
    if (auto partner = find_partner(path, ext)) return *partner;
    const std::string stem = split_name(path).first;
    throw FormatError(path.string(), field, stem + ext + " or " + stem + ext + ".gz beside it", "no such file");
}

/// For a segment whose length is known before decompression (plain data), checks that
/// file_offset + offset + bytes == file size (larger with allow_trailing); the field named is
/// "file size". Compressed segments are checked while streaming instead.
void check_segment_size(const DataSegment& segment) {
    const std::uint64_t size = file_size_or_throw(segment.path);
    const bool compressed = segment.compression == Compression::zlib ||
                            (segment.compression == Compression::detect && (segment.file_offset > 0 || is_gzip(segment.path)));
    if (compressed || segment.bytes == DataSegment::kToEnd) return;  // checked while streaming
    const std::uint64_t header = segment.file_offset + segment.offset;
    const std::uint64_t expected = header + segment.bytes;
    if (size == expected || (segment.allow_trailing && size > expected)) return;
    throw FormatError(segment.path.string(), "file size",
                      std::to_string(expected) + " bytes (" + std::to_string(header) + " header + " +
                          std::to_string(segment.bytes) + " samples)",
                      std::to_string(size) + " bytes");
}

}  // namespace

VolumeSource read_nifti_or_analyze(const std::filesystem::path& path) {
    const std::string ext = split_name(path).second;
    const std::filesystem::path header_path = ext == ".img" ? require_partner(path, ".hdr", "header file") : path;

    const std::vector<unsigned char> bytes = read_prefix(header_path, kNiftiHeaderBytes);
    NiftiAnalyzeHeader parsed = parse_nifti_analyze_header(bytes.data(), bytes.size(), header_path);
    if (split_name(header_path).second == ".nii" && !parsed.single_file)
        throw FormatError(header_path.string(), "magic", "\"n+1\" (a .nii file holds its samples)",
                          parsed.header.format == "nifti" ? "\"ni1\" (a header-only pair)" : "none (Analyze 7.5)");

    DataSegment segment;
    if (parsed.single_file) segment.path = header_path;
    else segment.path = ext == ".img" ? path : require_partner(header_path, ".img", "image file");
    segment.offset = parsed.vox_offset;
    segment.bytes = parsed.volume_bytes;
    segment.allow_trailing = parsed.all_bytes > parsed.volume_bytes;
    if (!is_gzip(segment.path)) {
        DataSegment whole = segment;  // the file must hold every volume, even if only the first is read
        whole.bytes = parsed.all_bytes;
        check_segment_size(whole);
    }

    VolumeSource source;
    source.header = std::move(parsed.header);
    source.header.path = path;
    source.segments.push_back(std::move(segment));
    return source;
}

}  // namespace vdbmesh::detail
