// Tokenizing and number parsing for the text mesh formats (ASCII STL, ASCII PLY, OBJ).
// Numbers are parsed with std::from_chars (correctly rounded), floats directly as float so
// that shortest round-trip output reads back bit-identical.
#include <cmath>

#include "io/mesh_io_detail.h"

namespace vdbmesh::detail {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

}  // namespace

std::string_view TextCursor::token() {
    while (pos_ < size_ && is_space(data_[pos_])) {
        if (data_[pos_] == '\n') ++line_;
        ++pos_;
    }
    const std::size_t begin = pos_;
    while (pos_ < size_ && !is_space(data_[pos_])) ++pos_;
    return {data_ + begin, pos_ - begin};
}

bool TextCursor::line(std::string_view& text) {
    if (pos_ >= size_) return false;
    const std::size_t begin = pos_;
    while (pos_ < size_ && data_[pos_] != '\n') ++pos_;
    std::size_t end = pos_;
    if (end > begin && data_[end - 1] == '\r') --end;
    if (pos_ < size_) ++pos_, ++line_;
    text = {data_ + begin, end - begin};
    return true;
}

bool TextCursor::at_end() {
    while (pos_ < size_ && is_space(data_[pos_])) {
        if (data_[pos_] == '\n') ++line_;
        ++pos_;
    }
    return pos_ >= size_;
}

bool parse_float(std::string_view text, float& value) {
    if (!text.empty() && text[0] == '+') text.remove_prefix(1);
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc() && end == text.data() + text.size() && !text.empty() && std::isfinite(value);
}

bool parse_double_value(std::string_view text, double& value) {
    if (!text.empty() && text[0] == '+') text.remove_prefix(1);
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc() && end == text.data() + text.size() && !text.empty() && std::isfinite(value);
}

bool parse_integer(std::string_view text, std::int64_t& value) {
    if (!text.empty() && text[0] == '+') text.remove_prefix(1);
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc() && end == text.data() + text.size() && !text.empty();
}

}  // namespace vdbmesh::detail
