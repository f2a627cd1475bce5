#pragma once
/// @file parse_util.h
/// @brief Checked text conversions and file helpers shared by the parsers of every stage
/// (volume headers in read and write, mesh files in io). Every failure is a FormatError
/// naming the file, the field, what was expected and what was found. In vdbmesh::detail:
/// shared between the stages, not a stable API.

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>


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

/// Each of @a values written by @a to_text, joined by @a separator: DICOM's multi-valued
/// strings ("1\\2\\3") in reader messages and writer elements.
template <class Values, class ToText>
std::string join_values(const Values& values, std::string_view separator, ToText to_text) {
    std::string text;
    for (const auto& value : values) {
        if (!text.empty()) text += separator;
        text += to_text(value);
    }
    return text;
}

/// Checks dims > 0, that the product and product * @a sample_bytes fit in 63 bits;
/// @a field names the header field in the error ("dim", "Resolution", "sizes").
void check_dims(const std::filesystem::path& file, const std::string& field, const std::array<std::int64_t, 3>& dims,
                std::size_t sample_bytes);

/// Reads at most @a max_bytes from the start of @a path, gunzipping when it is gzip.
/// Throws FormatError when the file cannot be opened.
std::vector<unsigned char> read_prefix(const std::filesystem::path& path, std::size_t max_bytes);

/// Size of @a path on disk; throws FormatError when it does not exist.
std::uint64_t file_size_or_throw(const std::filesystem::path& path);

/// True when the file starts with the gzip magic bytes.
bool is_gzip(const std::filesystem::path& path);

/// zlib's gzerror() text without the name zlib gives the stream in front of it
/// (@a stream_name: "<fd:3>" for gzdopen(3, ...), the path for gzopen()): our messages name
/// the file themselves. "corrupt data" when there is no text.
std::string gzip_error_reason(const char* message, const std::string& stream_name);

}  // namespace vdbmesh::detail
