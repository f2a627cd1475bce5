#pragma once
// Label maps for the commands (issue 31): the options `--labels` and `--label-names` shared by
// info, mesh and measure, the map read into memory with its name table, and names for files.

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common_options.h"
#include "vdbmesh/labels.h"

namespace vdbmesh::cli {

/// --labels all|LIST and --label-names FILE.
struct LabelFlags {
    std::optional<std::string> labels;  ///< set: the input is a label map (and these labels are meant)
    std::string names;                  ///< a table to use instead of the one beside the file
};
/// Adds both options; @a labels_help says what --labels does in this command.
void add_label_flags(CLI::App& command, LabelFlags& flags, const std::string& labels_help);

/// A label map in memory and the names of its labels.
struct LabelInput {
    LabelVolume volume;
    LabelTable table;
    std::string table_path;  ///< empty: no table
};

/// The name table: --label-names, else the one beside the scan (find_label_table()), else none.
LabelTable load_label_table(const std::string& scan, const LabelFlags& flags, std::string& table_path);

/// Reads the scan as a label map (FormatError naming the file and sample when it is not one).
LabelInput load_label_input(const std::vector<std::string>& inputs, const ReadFlags& read, const LabelFlags& flags);

/// A label's name made safe for a file name (letters, digits, - _ . kept; others become _).
std::string file_safe(const std::string& name);

}  // namespace vdbmesh::cli
