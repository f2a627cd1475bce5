#pragma once
// Private: the layer shared by the text-header formats (OpenQVis .dat, MetaImage .mhd/.mha,
// NRRD .nrrd/.nhdr): lines, "key <separator> value" fields, number lists, numbered data
// file names, data file paths and sizes, and the affine built from per-axis vectors.
// Everything here works on header text already in memory and touches the disk only to ask
// whether a data file exists and how long it is.

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "vdbmesh/read.h"

namespace vdbmesh::detail {

/// Longest header text read from disk (a .nhdr with a long LIST of files still fits).
constexpr std::size_t kMaxHeaderBytes = std::size_t{1} << 20;

/// One line of a header, without its line end ("\n" or "\r\n").
struct HeaderLine {
    std::string_view text;
    std::size_t end = 0;  ///< offset just past the line end: where the next line (or the data) starts
    int number = 0;       ///< 1-based, for messages
};

/// Walks the lines of a header text.
class HeaderLines {
public:
    explicit HeaderLines(std::string_view text) : text_(text) {}
    /// The next line; false at the end of the text.
    bool next(HeaderLine& line);
    /// "line 12", the name of a line in messages.
    static std::string name(const HeaderLine& line) { return "line " + std::to_string(line.number); }

private:
    std::string_view text_;
    std::size_t position_ = 0;
    int number_ = 0;
};

/// A line split at the first @a separator, both sides trimmed; nullopt when the separator is absent.
std::optional<std::pair<std::string_view, std::string_view>> split_field(std::string_view line,
                                                                          std::string_view separator);

/// A value as shown in messages: quoted, cut after 40 characters.
std::string shown(std::string_view value);

/// The fields of a header, looked up without regard to case.
class HeaderFields {
public:
    explicit HeaderFields(std::filesystem::path file) : file_(std::move(file)) {}
    /// Adds a field; a second line for the same key is a FormatError.
    void add(std::string_view key, std::string_view value);
    /// The value of @a key, or nullopt.
    std::optional<std::string_view> find(std::string_view key) const;
    /// The first of the synonyms @a keys present, as (key as spelled in the call, value).
    std::optional<std::pair<std::string, std::string_view>> find_any(const std::vector<std::string>& keys) const;
    /// The value of @a key; a FormatError naming the key when it is missing.
    std::string_view require(std::string_view key) const;
    const std::filesystem::path& file() const { return file_; }

private:
    std::filesystem::path file_;
    std::vector<std::pair<std::string, std::string>> fields_;  // lower-cased key, value
};

/// Exactly @a count integers separated by spaces/tabs; FormatError naming @a field otherwise.
std::vector<std::int64_t> parse_int_list(const std::filesystem::path& file, const std::string& field,
                                         std::string_view value, std::size_t count);
/// Exactly @a count finite numbers separated by spaces/tabs (commas too when @a commas).
std::vector<double> parse_double_list(const std::filesystem::path& file, const std::string& field,
                                      std::string_view value, std::size_t count, bool commas = false);
/// "True"/"False" (also "1"/"0"), any case.
bool parse_bool(const std::filesystem::path& file, const std::string& field, std::string_view value);

/// Product of @a sizes, which check_dims() has already bounded.
std::int64_t product(const std::vector<std::int64_t>& sizes, std::size_t begin, std::size_t end);

/// The names a printf-like pattern with one integer conversion ("%d", "%03d", "%i"; "%%" is
/// a percent sign) gives for first, first + step, ... up to last inclusive. Throws FormatError
/// when the pattern is not of that form, step is 0 or points away from last, or the count
/// differs from @a expected_count (the number of files the dims call for).
std::vector<std::string> numbered_names(const std::filesystem::path& file, const std::string& field,
                                        std::string_view pattern, std::int64_t first, std::int64_t last,
                                        std::int64_t step, std::int64_t expected_count);

/// @a name relative to the header's folder (absolute names are kept).
std::filesystem::path data_path(const std::filesystem::path& header, std::string_view name);

/// A parsed header (MetaImage, NRRD): its fields, where the text after them starts (the data
/// inside the file; 0 when nothing follows), and the file names on the lines after a "LIST"
/// data file value.
struct TextHeader {
    HeaderFields fields;
    std::size_t end = 0;
    std::vector<std::string> list_files;
};

/// The data files in order (the header's own file for data inside it) and the dimension of
/// the samples each one holds.
struct DataFiles {
    std::vector<std::filesystem::path> paths;
    std::size_t dimension = 0;
    bool inside_header = false;  ///< MetaImage LOCAL, NRRD attached data
};

/// The files a data file value names as "LIST [d]" (the header's list_files, which must be
/// as many as the volume has d-dimensional pieces) or "pattern min max step [d]"
/// (numbered_names()), d read by @a parse_dimension (default: one less than the volume's);
/// MetaImage's ElementDataFile and NRRD's "data file" share these forms. Empty for any other
/// value. @a words: the value's words; @a field names it in errors.
std::optional<DataFiles> listed_data_files(const TextHeader& header, const std::string& field,
                                           const std::vector<std::string>& words, const std::vector<std::int64_t>& sizes,
                                           const std::function<std::size_t(std::string_view)>& parse_dimension);
/// FormatError(header, field, "an existing data file", path) when @a path is not a readable file.
void require_data_file(const std::filesystem::path& header, const std::string& field, const std::filesystem::path& path);
/// The file offset at which the last @a bytes of @a path start ("data at the end of the file").
std::uint64_t tail_offset(const std::filesystem::path& header, const std::string& field,
                          const std::filesystem::path& path, std::uint64_t bytes);
/// For uncompressed data: the data file must hold exactly file_offset + offset + bytes bytes.
void check_plain_data_size(const std::filesystem::path& header, const DataSegment& segment);

/// Sets spacing and index_to_world from the world vector of each index axis (one voxel step
/// along i, j, k) and the world position of voxel (0, 0, 0). A zero vector is a FormatError.
void set_axes(VolumeHeader& header, const std::string& field, const std::array<std::array<double, 3>, 3>& axes,
              const std::array<double, 3>& origin);

/// The start of a header file as text (gunzipped when the file is gzip), at most kMaxHeaderBytes.
std::string read_header_text(const std::filesystem::path& path);

}  // namespace vdbmesh::detail
