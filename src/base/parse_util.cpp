#include "vdbmesh/parse_util.h"

#include <zlib.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>

#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

std::string quoted(std::string_view text) {
    constexpr std::size_t kMaxShown = 40;
    std::string shown(text.substr(0, kMaxShown));
    if (text.size() > kMaxShown) shown += "...";
    return "\"" + shown + "\"";
}

}  // namespace

std::string_view trim(std::string_view text) {
    const char* kSpace = " \t\r\n";
    const auto first = text.find_first_not_of(kSpace);
    if (first == std::string_view::npos) return {};
    const auto last = text.find_last_not_of(kSpace);
    return text.substr(first, last - first + 1);
}

std::string to_lower(std::string_view text) {
    std::string out(text);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

std::vector<std::string> split_words(std::string_view text, bool commas) {
    std::vector<std::string> words;
    std::string current;
    for (char c : text) {
        const bool separator = c == ' ' || c == '\t' || c == '\r' || c == '\n' || (commas && c == ',');
        if (!separator) {
            current += c;
        } else if (!current.empty()) {
            words.push_back(std::move(current));
            current.clear();
        }
    }
    if (!current.empty()) words.push_back(std::move(current));
    return words;
}

std::int64_t parse_int(const std::filesystem::path& file, const std::string& field, std::string_view text) {
    text = trim(text);
    if (!text.empty() && text.front() == '+') text.remove_prefix(1);
    std::int64_t value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size())
        throw FormatError(file.string(), field, "an integer", quoted(text));
    return value;
}

double parse_double(const std::filesystem::path& file, const std::string& field, std::string_view text) {
    text = trim(text);
    if (!text.empty() && text.front() == '+') text.remove_prefix(1);
    double value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
        throw FormatError(file.string(), field, "a finite number", quoted(text));
    return value;
}

void check_dims(const std::filesystem::path& file, const std::string& field, const std::array<std::int64_t, 3>& dims,
                std::size_t sample_bytes) {
    constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
    std::int64_t bytes = static_cast<std::int64_t>(sample_bytes);
    for (int axis = 0; axis < 3; ++axis) {
        if (dims[axis] <= 0)
            throw FormatError(file.string(), field + "[" + std::to_string(axis) + "]", "> 0", std::to_string(dims[axis]));
        if (bytes > kMax / dims[axis])
            throw FormatError(file.string(), field, "a sample count whose byte size fits in 63 bits",
                              std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " +
                                  std::to_string(dims[2]) + " x " + std::to_string(sample_bytes) + " bytes");
        bytes *= dims[axis];
    }
}

std::vector<unsigned char> read_prefix(const std::filesystem::path& path, std::size_t max_bytes) {
    gzFile file = gzopen(path.c_str(), "rb");
    if (!file) throw FormatError(path.string(), "cannot open the file");
    std::vector<unsigned char> bytes(max_bytes);
    std::size_t filled = 0;
    while (filled < max_bytes) {
        const unsigned chunk = static_cast<unsigned>(std::min<std::size_t>(max_bytes - filled, 1u << 30));
        const int got = gzread(file, bytes.data() + filled, chunk);
        if (got <= 0) break;
        filled += static_cast<std::size_t>(got);
    }
    int status = Z_OK;
    const std::string reason = gzip_error_reason(gzerror(file, &status), path.string());
    gzclose(file);
    if (status != Z_OK && status != Z_BUF_ERROR) throw FormatError(path.string(), "gzip stream", "valid compressed data", reason);
    bytes.resize(filled);
    return bytes;
}

std::uint64_t file_size_or_throw(const std::filesystem::path& path) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) throw FormatError(path.string(), "file", "an existing, readable file", "missing (" + ec.message() + ")");
    return size;
}

bool is_gzip(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char magic[2] = {0, 0};
    in.read(reinterpret_cast<char*>(magic), 2);
    return in.gcount() == 2 && magic[0] == 0x1f && magic[1] == 0x8b;
}

std::string gzip_error_reason(const char* message, const std::string& stream_name) {
    std::string text = message ? message : "";
    const std::string prefix = stream_name + ": ";
    if (text.compare(0, prefix.size(), prefix) == 0) text.erase(0, prefix.size());
    return text.empty() ? "corrupt data" : text;
}

}  // namespace vdbmesh::detail
