// The line-and-field layer shared by the OpenQVis, MetaImage and NRRD header parsers.

#include "text_header.h"

#include <cmath>
#include <limits>

#include "vdbmesh/parse_util.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

/// More data files than this is not a scan (and would only cost memory to list).
constexpr std::int64_t kMaxDataFiles = std::int64_t{1} << 20;
/// Bound on pattern numbers, so that (last - first) cannot overflow.
constexpr std::int64_t kMaxPatternNumber = std::int64_t{1} << 62;

/// A pattern split around its single integer conversion.
struct NumberPattern {
    std::string prefix, suffix;
    std::size_t width = 0;
    bool zero_pad = false;
};

NumberPattern parse_number_pattern(const std::filesystem::path& file, const std::string& field,
                                   std::string_view pattern) {
    const std::string expected = "a file name pattern with one %d conversion (like name%03d.raw)";
    NumberPattern result;
    int conversions = 0;
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        std::string& out = conversions == 0 ? result.prefix : result.suffix;
        if (pattern[i] != '%') {
            out += pattern[i];
            continue;
        }
        if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
            out += '%';
            ++i;
            continue;
        }
        std::size_t j = i + 1;
        if (j < pattern.size() && pattern[j] == '0') {
            result.zero_pad = true;
            ++j;
        }
        std::size_t width = 0;
        while (j < pattern.size() && pattern[j] >= '0' && pattern[j] <= '9' && width < 100)
            width = width * 10 + static_cast<std::size_t>(pattern[j++] - '0');
        if (j >= pattern.size() || (pattern[j] != 'd' && pattern[j] != 'i') || width > 20)
            throw FormatError(file.string(), field, expected, shown(pattern));
        result.width = width;
        ++conversions;
        i = j;
    }
    if (conversions != 1) throw FormatError(file.string(), field, expected, shown(pattern));
    return result;
}

std::string format_number(const NumberPattern& pattern, std::int64_t number) {
    std::string digits = std::to_string(number < 0 ? -number : number);
    const std::size_t sign = number < 0 ? 1 : 0;
    if (pattern.zero_pad && digits.size() + sign < pattern.width)
        digits.insert(0, pattern.width - digits.size() - sign, '0');
    if (number < 0) digits.insert(0, 1, '-');
    if (digits.size() < pattern.width) digits.insert(0, pattern.width - digits.size(), ' ');
    return pattern.prefix + digits + pattern.suffix;
}

}  // namespace

bool HeaderLines::next(HeaderLine& line) {
    if (position_ >= text_.size()) return false;
    const std::size_t newline = text_.find('\n', position_);
    const std::size_t stop = newline == std::string_view::npos ? text_.size() : newline;
    line.text = text_.substr(position_, stop - position_);
    if (!line.text.empty() && line.text.back() == '\r') line.text.remove_suffix(1);
    line.end = newline == std::string_view::npos ? text_.size() : newline + 1;
    line.number = ++number_;
    position_ = line.end;
    return true;
}

std::optional<std::pair<std::string_view, std::string_view>> split_field(std::string_view line,
                                                                          std::string_view separator) {
    const std::size_t at = line.find(separator);
    if (at == std::string_view::npos) return std::nullopt;
    return std::make_pair(trim(line.substr(0, at)), trim(line.substr(at + separator.size())));
}

std::string shown(std::string_view value) {
    constexpr std::size_t kMaxShown = 40;
    std::string text(value.substr(0, kMaxShown));
    for (char& c : text)
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
    if (value.size() > kMaxShown) text += "...";
    return "\"" + text + "\"";
}

void HeaderFields::add(std::string_view key, std::string_view value) {
    std::string lower = to_lower(key);
    if (find(lower)) throw FormatError(file_.string(), std::string(key), "a single line", "two lines");
    fields_.emplace_back(std::move(lower), std::string(value));
}

std::optional<std::string_view> HeaderFields::find(std::string_view key) const {
    const std::string lower = to_lower(key);
    for (const auto& [name, value] : fields_)
        if (name == lower) return std::string_view(value);
    return std::nullopt;
}

std::optional<std::pair<std::string, std::string_view>> HeaderFields::find_any(
    const std::vector<std::string>& keys) const {
    for (const std::string& key : keys)
        if (const auto value = find(key)) return std::make_pair(key, *value);
    return std::nullopt;
}

std::string_view HeaderFields::require(std::string_view key) const {
    if (const auto value = find(key)) return *value;
    throw FormatError(file_.string(), std::string(key), "a \"" + std::string(key) + "\" line", "none");
}

std::vector<std::int64_t> parse_int_list(const std::filesystem::path& file, const std::string& field,
                                         std::string_view value, std::size_t count) {
    const auto words = split_words(value);
    if (words.size() != count)
        throw FormatError(file.string(), field, std::to_string(count) + " integers", shown(value));
    std::vector<std::int64_t> numbers;
    for (const std::string& word : words) numbers.push_back(parse_int(file, field, word));
    return numbers;
}

std::vector<double> parse_double_list(const std::filesystem::path& file, const std::string& field,
                                      std::string_view value, std::size_t count, bool commas) {
    const auto words = split_words(value, commas);
    if (words.size() != count)
        throw FormatError(file.string(), field, std::to_string(count) + " numbers", shown(value));
    std::vector<double> numbers;
    for (const std::string& word : words) numbers.push_back(parse_double(file, field, word));
    return numbers;
}

bool parse_bool(const std::filesystem::path& file, const std::string& field, std::string_view value) {
    const std::string lower = to_lower(trim(value));
    if (lower == "true" || lower == "1") return true;
    if (lower == "false" || lower == "0") return false;
    throw FormatError(file.string(), field, "True or False", shown(value));
}

std::int64_t product(const std::vector<std::int64_t>& sizes, std::size_t begin, std::size_t end) {
    std::int64_t result = 1;
    for (std::size_t i = begin; i < end && i < sizes.size(); ++i) result *= sizes[i];
    return result;
}

std::vector<std::string> numbered_names(const std::filesystem::path& file, const std::string& field,
                                        std::string_view pattern, std::int64_t first, std::int64_t last,
                                        std::int64_t step, std::int64_t expected_count) {
    const NumberPattern parsed = parse_number_pattern(file, field, pattern);
    const auto out_of_range = [](std::int64_t n) { return n > kMaxPatternNumber || n < -kMaxPatternNumber; };
    if (out_of_range(first) || out_of_range(last))
        throw FormatError(file.string(), field, "file numbers within +-2^62",
                          std::to_string(first) + " to " + std::to_string(last));
    const std::int64_t span = last - first;
    if (step == 0 || (span != 0 && (span > 0) != (step > 0)))
        throw FormatError(file.string(), field, "a step leading from " + std::to_string(first) + " to " + std::to_string(last),
                          std::to_string(step));
    const std::int64_t count = span / step + 1;
    if (count != expected_count)
        throw FormatError(file.string(), field, std::to_string(expected_count) + " data files (one per piece the sizes call for)",
                          std::to_string(count) + " files");
    if (count > kMaxDataFiles)
        throw FormatError(file.string(), field, "at most " + std::to_string(kMaxDataFiles) + " data files",
                          std::to_string(count));
    std::vector<std::string> names;
    for (std::int64_t i = 0; i < count; ++i) names.push_back(format_number(parsed, first + i * step));
    return names;
}

std::filesystem::path data_path(const std::filesystem::path& header, std::string_view name) {
    const std::filesystem::path relative(name);
    if (relative.is_absolute()) return relative;
    return header.parent_path() / relative;
}

void require_data_file(const std::filesystem::path& header, const std::string& field, const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw FormatError(header.string(), field, "an existing data file", "\"" + path.string() + "\" (not found)");
}

std::uint64_t tail_offset(const std::filesystem::path& header, const std::string& field,
                          const std::filesystem::path& path, std::uint64_t bytes) {
    const std::uint64_t size = file_size_or_throw(path);
    if (size < bytes)
        throw FormatError(header.string(), field,
                          "a data file of at least " + std::to_string(bytes) + " bytes (the samples at its end)",
                          "\"" + path.string() + "\" of " + std::to_string(size) + " bytes");
    return size - bytes;
}

void check_plain_data_size(const std::filesystem::path& header, const DataSegment& segment) {
    const std::uint64_t size = file_size_or_throw(segment.path);
    const std::uint64_t skipped = segment.file_offset + segment.offset;
    const bool overflow = skipped < segment.file_offset || skipped > std::numeric_limits<std::uint64_t>::max() - segment.bytes;
    if (overflow || size != skipped + segment.bytes)
        throw FormatError(segment.path.string(), "file size",
                          (overflow ? std::string("a size in 64 bits") : std::to_string(skipped + segment.bytes) + " bytes") +
                              " (" + std::to_string(skipped) + " skipped + " + std::to_string(segment.bytes) +
                              " of samples, per " + header.filename().string() + ")",
                          std::to_string(size) + " bytes");
}

void set_axes(VolumeHeader& header, const std::string& field, const std::array<std::array<double, 3>, 3>& axes,
              const std::array<double, 3>& origin) {
    for (int axis = 0; axis < 3; ++axis) {
        const auto& v = axes[axis];
        const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (!(length > 0) || !std::isfinite(length))
            throw FormatError(header.path.string(), field, "a non-zero, finite step along every axis",
                              "axis " + std::to_string(axis) + " of length " + std::to_string(length));
        header.spacing[axis] = length;
        for (int row = 0; row < 3; ++row) header.index_to_world[row][axis] = v[row];
    }
    for (int row = 0; row < 3; ++row) header.index_to_world[row][3] = origin[row];
}

std::string read_header_text(const std::filesystem::path& path) {
    const std::vector<unsigned char> bytes = read_prefix(path, kMaxHeaderBytes);
    return std::string(bytes.begin(), bytes.end());
}

std::optional<DataFiles> listed_data_files(const TextHeader& header, const std::string& field,
                                           const std::vector<std::string>& words, const std::vector<std::int64_t>& sizes,
                                           const std::function<std::size_t(std::string_view)>& parse_dimension) {
    const std::filesystem::path& path = header.fields.file();
    const std::size_t ndims = sizes.size();
    DataFiles files;
    if (!words.empty() && to_lower(words[0]) == "list" && words.size() <= 2) {
        files.dimension = words.size() == 2 ? parse_dimension(words[1]) : ndims - 1;
        const std::int64_t count = product(sizes, files.dimension, ndims);
        if (static_cast<std::int64_t>(header.list_files.size()) != count)
            throw FormatError(path.string(), field, std::to_string(count) + " file names after LIST",
                              std::to_string(header.list_files.size()));
        for (const std::string& name : header.list_files) files.paths.push_back(data_path(path, name));
        return files;
    }
    if (!words.empty() && words[0].find('%') != std::string::npos && (words.size() == 4 || words.size() == 5)) {
        files.dimension = words.size() == 5 ? parse_dimension(words[4]) : ndims - 1;
        const auto names = numbered_names(path, field, words[0], parse_int(path, field, words[1]),
                                          parse_int(path, field, words[2]), parse_int(path, field, words[3]),
                                          product(sizes, files.dimension, ndims));
        for (const std::string& name : names) files.paths.push_back(data_path(path, name));
        return files;
    }
    return std::nullopt;
}

}  // namespace vdbmesh::detail
