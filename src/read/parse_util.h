#pragma once
// Private: checked conversions shared by the header parsers. Every failure is a
// FormatError naming the file, the field, what was expected and what was found.

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "vdbmesh/read.h"

namespace vdbmesh::detail {

/// Parses a whole decimal integer; throws FormatError("integer", text) otherwise.
std::int64_t parse_int(const std::filesystem::path& file, const std::string& field, std::string_view text);
/// Parses a finite floating-point number.
double parse_double(const std::filesystem::path& file, const std::string& field, std::string_view text);
/// Splits on spaces/tabs (and commas when @a commas) and drops empty pieces.
std::vector<std::string> split_words(std::string_view text, bool commas = false);
/// Trims spaces, tabs, CR and LF at both ends.
std::string_view trim(std::string_view text);
/// Lower-cased copy.
std::string to_lower(std::string_view text);

/// Checks dims > 0, that the product and product * element size fit in 63 bits;
/// @a field names the header field in the error ("dim", "Resolution", "sizes").
void check_dims(const std::filesystem::path& file, const std::string& field, const std::array<std::int64_t, 3>& dims,
                SampleType type);

/// Reads at most @a max_bytes from the start of @a path, gunzipping when it is gzip.
/// Throws FormatError when the file cannot be opened.
std::vector<unsigned char> read_prefix(const std::filesystem::path& path, std::size_t max_bytes);

/// Size of @a path on disk; throws FormatError when it does not exist.
std::uint64_t file_size_or_throw(const std::filesystem::path& path);

/// True when the file starts with the gzip magic bytes.
bool is_gzip(const std::filesystem::path& path);

/// For a segment whose length is known before decompression (plain data), checks that
/// file_offset + offset + bytes == file size (larger with allow_trailing); the field named is
/// "file size". Compressed segments are checked while streaming instead.
void check_segment_size(const DataSegment& segment);

}  // namespace vdbmesh::detail
