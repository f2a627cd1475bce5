// Headerless raw volumes (--raw-dims X,Y,Z, --raw-type, --raw-endian, --spacing,
// --header-bytes): the samples, x fastest, in one file or split over several read in order
// (ReadOptions::raw_more_files). Each file may be plain or gzip, including several gzip
// members one after the other. --header-bytes are skipped at the start of the first file
// (after decompression). The files together must hold exactly dims x sample size bytes.

#include <cmath>

#include "formats.h"
#include "vdbmesh/parse_util.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

/// Deflate expands its input at most 1032-fold (a 258-byte match in 2 bits at best, RFC 1951),
/// so a gzip file of n bytes holds at most 1032 n bytes.
constexpr std::uint64_t kMaxDeflateRatio = 1032;

/// When no file is gzipped, checks their sizes now rather than after streaming them all;
/// compressed files are checked while they are read (VolumeReader), and now only against what
/// they can hold at most: dims too large for the files are refused before any allocation, with
/// the message a plain file gets.
void check_plain_sizes(const VolumeSource& source, std::uint64_t header_bytes) {
    std::uint64_t total = 0, most = 0;
    bool compressed = false;
    for (const DataSegment& segment : source.segments) {
        const std::uint64_t size = file_size_or_throw(segment.path);
        const bool gzip = is_gzip(segment.path);
        total += size;
        most += gzip ? size * kMaxDeflateRatio : size;
        compressed = compressed || gzip;
    }
    const std::string file = source.header.path.string();
    if (compressed) {
        const std::uint64_t sample_bytes =
            static_cast<std::uint64_t>(source.header.voxel_count()) * sample_size(source.header.type);
        if (most < header_bytes || most - header_bytes < sample_bytes)
            throw FormatError(file, "sample data", describe_sample_bytes(source.header, source.segments.size()),
                              "at most " + std::to_string(most - std::min(most, header_bytes)) +
                                  " bytes (truncated: gzip holds at most " + std::to_string(kMaxDeflateRatio) + " times its size)");
        return;
    }
    const std::uint64_t first_size = file_size_or_throw(source.segments.front().path);
    if (header_bytes > first_size)
        throw FormatError(file, "--header-bytes", "at most the file size, " + std::to_string(first_size),
                          std::to_string(header_bytes));
    const std::uint64_t sample_bytes =
        static_cast<std::uint64_t>(source.header.voxel_count()) * sample_size(source.header.type);
    const std::uint64_t found = total - header_bytes;
    const std::string expected = describe_sample_bytes(source.header, source.segments.size());
    if (found < sample_bytes)
        throw FormatError(file, "sample data", expected, "only " + std::to_string(found) + " bytes (truncated)");
    if (found > sample_bytes)
        throw FormatError(file, "trailing data", expected, std::to_string(found - sample_bytes) + " more bytes");
}

}  // namespace

VolumeSource read_raw(const std::filesystem::path& path, const ReadOptions& options) {
    if (!options.raw_dims) throw UsageError("headerless raw input needs --raw-dims X,Y,Z");
    for (double s : options.raw_spacing)
        if (!(std::isfinite(s) && s > 0)) throw UsageError("--spacing: expected three positive numbers");

    VolumeSource source;
    VolumeHeader& h = source.header;
    h.format = "raw";
    h.path = path;
    h.dims = *options.raw_dims;
    h.type = options.raw_type;
    h.byte_order = options.raw_byte_order;
    h.spacing = options.raw_spacing;
    h.index_to_world = axis_aligned_affine(h.spacing);
    check_dims(path, "--raw-dims", h.dims, sample_size(h.type));

    DataSegment first;
    first.path = path;
    first.offset = options.raw_header_bytes;
    source.segments.push_back(first);
    for (const auto& more : options.raw_more_files) {
        DataSegment part;
        part.path = more;
        source.segments.push_back(part);
    }
    check_plain_sizes(source, options.raw_header_bytes);
    return source;
}

}  // namespace vdbmesh::detail
