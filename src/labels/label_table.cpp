// Label tables: value -> name (and colour), as the atlases and segmentation tools write them.

#include <cctype>
#include <fstream>
#include <string>

#include "vdbmesh/error.h"
#include "vdbmesh/labels.h"
#include "vdbmesh/parse_util.h"

namespace vdbmesh {
namespace {

bool is_integer(const std::string& word) {
    return !word.empty() && std::all_of(word.begin(), word.end(), [](unsigned char c) { return std::isdigit(c); });
}

/// ITK-SNAP quotes the name, which may hold spaces: the text between the first pair of quotes.
std::optional<std::string> quoted_name(std::string_view line) {
    const std::size_t open = line.find('"');
    if (open == std::string_view::npos) return std::nullopt;
    const std::size_t close = line.find('"', open + 1);
    if (close == std::string_view::npos) return std::nullopt;
    return std::string(line.substr(open + 1, close - open - 1));
}

std::uint8_t colour_component(const std::filesystem::path& file, const std::string& field, const std::string& word) {
    const std::int64_t value = detail::parse_int(file, field, word);
    if (value < 0 || value > 255) throw FormatError(file.string(), field, "a colour component 0..255", word);
    return std::uint8_t(value);
}

/// One non-comment line: `value name [code]` (MRIcron), `value name R G B A` (FreeSurfer) or
/// `value R G B A visible mesh "name"` (ITK-SNAP).
std::pair<std::uint32_t, LabelEntry> parse_row(const std::filesystem::path& file, const std::string& field,
                                               std::string_view line) {
    const std::vector<std::string> words = detail::split_words(line);
    const std::int64_t value = detail::parse_int(file, field + " label value", words[0]);
    if (value < 0 || value > std::int64_t(kMaxLabel))
        throw FormatError(file.string(), field + " label value", "0.." + std::to_string(kMaxLabel), words[0]);
    LabelEntry entry;
    if (const std::optional<std::string> name = quoted_name(line)) {  // ITK-SNAP
        if (words.size() < 4) throw FormatError(file.string(), field, "value R G B ... \"name\"", std::string(line));
        entry.name = *name;
        entry.color = {colour_component(file, field + " R", words[1]), colour_component(file, field + " G", words[2]),
                       colour_component(file, field + " B", words[3])};
    } else {
        if (words.size() < 2) throw FormatError(file.string(), field, "a label value and a name", std::string(line));
        entry.name = words[1];
        if (words.size() >= 5 && is_integer(words[2]) && is_integer(words[3]) && is_integer(words[4]))  // FreeSurfer
            entry.color = {colour_component(file, field + " R", words[2]), colour_component(file, field + " G", words[3]),
                           colour_component(file, field + " B", words[4])};
    }
    return {std::uint32_t(value), entry};
}

}  // namespace

LabelTable read_label_table(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw FormatError(path.string(), "cannot open the label table");
    LabelTable table;
    std::string line;
    for (std::size_t number = 1; std::getline(in, line); ++number) {
        const std::string_view text = detail::trim(line);
        if (text.empty() || text.front() == '#') continue;
        const std::string field = "line " + std::to_string(number);
        auto [value, entry] = parse_row(path, field, text);
        if (!table.emplace(value, entry).second)
            throw FormatError(path.string(), field, "each label value once", std::to_string(value) + " again");
    }
    return table;
}

std::optional<std::filesystem::path> find_label_table(const std::filesystem::path& scan) {
    std::filesystem::path plain = scan;
    if (detail::to_lower(plain.extension().string()) == ".gz") plain.replace_extension();
    const std::filesystem::path stem = std::filesystem::path(plain).replace_extension();
    const std::filesystem::path candidates[] = {
        plain.string() + ".txt", stem.string() + ".txt", stem.string() + ".lut", stem.string() + "_LUT.txt",
        stem.string() + ".label"};
    for (const std::filesystem::path& candidate : candidates) {
        std::error_code error;
        if (std::filesystem::is_regular_file(candidate, error)) return candidate;
    }
    return std::nullopt;
}

std::vector<std::uint32_t> parse_label_list(const std::string& text) {
    if (text == "all") return {};
    std::vector<std::uint32_t> labels;
    const auto bad = [&](const std::string& piece) {
        return UsageError("--labels: expected \"all\" or label values like 3,5,10-12 (1.." + std::to_string(kMaxLabel) +
                          "), got \"" + piece + "\"");
    };
    for (const std::string& piece : detail::split_words(text, true)) {
        const std::size_t dash = piece.find('-', 1);
        const std::string first = piece.substr(0, dash);
        const std::string last = dash == std::string::npos ? first : piece.substr(dash + 1);
        if (!is_integer(first) || !is_integer(last) || first.size() > 6 || last.size() > 6) throw bad(piece);
        const std::uint32_t a = std::stoul(first), b = std::stoul(last);
        if (a == 0 || b < a || b > kMaxLabel) throw bad(piece);
        for (std::uint32_t v = a; v <= b; ++v) labels.push_back(v);
    }
    if (labels.empty()) throw bad(text);
    std::sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
    return labels;
}

}  // namespace vdbmesh
