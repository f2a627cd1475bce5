// Label maps for the commands: options, the map and its name table (label_input.h).

#include "label_input.h"

#include <cctype>

#include "load_grid.h"

namespace vdbmesh::cli {

void add_label_flags(CLI::App& command, LabelFlags& flags, const std::string& labels_help) {
    command.add_option("--labels", flags.labels, labels_help);
    command.add_option("--label-names", flags.names,
                       "Label table (value name per line: MRIcron .txt, FreeSurfer LUT, ITK-SNAP); default: the one beside the file")
        ->check(CLI::ExistingFile);
}

LabelTable load_label_table(const std::string& scan, const LabelFlags& flags, std::string& table_path) {
    if (!flags.names.empty()) {
        table_path = flags.names;
    } else if (const std::optional<std::filesystem::path> beside = find_label_table(scan)) {
        table_path = beside->string();
    }
    return table_path.empty() ? LabelTable{} : read_label_table(table_path);
}

LabelInput load_label_input(const std::vector<std::string>& inputs, const ReadFlags& read, const LabelFlags& flags) {
    LabelInput input;
    auto reader = open_scan(inputs, read);
    input.volume = read_label_volume(*reader);
    input.table = load_label_table(inputs.front(), flags, input.table_path);
    return input;
}

std::string file_safe(const std::string& name) {
    std::string safe = name;
    for (char& c : safe)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
    return safe;
}

}  // namespace vdbmesh::cli
