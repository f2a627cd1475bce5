#include "option_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "load_grid.h"
#include "vdbmesh/error.h"
#include "vdbmesh/points.h"

namespace vdbmesh::cli {

namespace {

// The roles are validators that accept anything and show nothing in --help, found by name.
const char* const kInputRole = "vdbmesh-input-files";
const char* const kReplaceableRole = "vdbmesh-replaceable-input";
const char* const kOutputRole = "vdbmesh-output-file";

CLI::Option* mark(CLI::Option* option, const char* role) {
    return option->check(CLI::Validator([](std::string&) { return std::string(); }, "", role));
}

bool has_role(CLI::Option* option, const char* role) {
    try {
        option->get_validator(role);
        return true;
    } catch (const CLI::OptionNotFound&) {
        return false;
    }
}

/// The name an option is given by on the command line. CLI11's get_name() is empty for a hidden
/// option (an empty group), which a message must still name (compare's retired --dmc-error).
std::string option_name(const CLI::Option* option) {
    if (!option->get_lnames().empty()) return "--" + option->get_lnames().front();
    if (!option->get_snames().empty()) return "-" + option->get_snames().front();
    return option->get_name();
}

/// The options of @a command and of its option groups (nameless subcommands).
std::vector<CLI::Option*> all_options(CLI::App& command) {
    std::vector<CLI::Option*> options = command.get_options();
    for (CLI::App* group : command.get_subcommands([](CLI::App* sub) { return sub->get_name().empty(); })) {
        const std::vector<CLI::Option*> more = all_options(*group);
        options.insert(options.end(), more.begin(), more.end());
    }
    return options;
}

/// True when @a text is wholly a number that is not finite: nan, inf, or one beyond a double.
bool non_finite_number(const std::string& text) {
    if (text.empty()) return false;
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    return end != text.c_str() && *end == '\0' && !std::isfinite(value);
}

/// The value, or an item of it when it is a list ("0,nan", "z:inf", "z=1e999").
bool has_non_finite_item(const std::string& value) {
    std::size_t start = 0;
    while (start <= value.size()) {
        const std::size_t end = std::min(value.find_first_of(",:=", start), value.size());
        if (non_finite_number(value.substr(start, end - start))) return true;
        start = end + 1;
    }
    return false;
}

void refuse_non_finite(const std::vector<CLI::Option*>& options) {
    for (const CLI::Option* option : options) {
        if (!option->nonpositional()) continue;  // file names
        for (const std::string& value : option->results()) {
            if (has_non_finite_item(value))
                throw UsageError(option_name(option) + ": expected a finite number, got \"" + value + "\"");
        }
    }
}

struct NamedFile {
    const CLI::Option* option;
    std::string path;
    bool input;             ///< else an output
    std::string listed_by;  ///< the input file that names this one (a .conf's scan), or empty
};

/// The files an input names besides itself, read with it: a .conf range-scan set's scans. A
/// file that cannot be listed is left to its reader to report.
std::vector<std::filesystem::path> files_named_by(const std::string& input) {
    if (lowercase_extension(input) != ".conf") return {};
    try {
        return conf_scan_files(input);
    } catch (const Error&) {
        return {};
    }
}

/// True when @a a and @a b name the same file: the same device and inode when both exist
/// (through any link), else the same path once made absolute and normal.
bool same_file(const std::string& a, const std::string& b) {
    std::error_code missing, error_a, error_b;  // equivalent() is false, with an error, when either does not exist
    if (std::filesystem::equivalent(a, b, missing)) return true;
    const std::filesystem::path path_a = std::filesystem::weakly_canonical(a, error_a);
    const std::filesystem::path path_b = std::filesystem::weakly_canonical(b, error_b);
    return !error_a && !error_b && path_a == path_b;
}

/// Refuses an output that is the same file as an input or as another output.
void refuse_outputs_naming_inputs(const std::vector<CLI::Option*>& options) {
    std::vector<NamedFile> inputs, outputs;
    for (CLI::Option* option : options) {
        const bool output = has_role(option, kOutputRole), replaceable = has_role(option, kReplaceableRole);
        if (!output && !replaceable && !has_role(option, kInputRole)) continue;
        for (const std::string& path : option->results()) {
            if (output) {
                outputs.push_back({option, path, false, ""});
            } else if (!replaceable) {
                inputs.push_back({option, path, true, ""});
                for (const std::filesystem::path& named : files_named_by(path)) inputs.push_back({option, named.string(), true, path});
            }
        }
    }
    for (std::size_t i = 0; i < outputs.size(); ++i) {
        const NamedFile& out = outputs[i];
        std::vector<NamedFile> others = inputs;
        others.insert(others.end(), outputs.begin(), outputs.begin() + std::ptrdiff_t(i));
        for (const NamedFile& other : others) {
            if (!same_file(out.path, other.path)) continue;
            const std::string listed = other.listed_by.empty() ? "" : " (listed in \"" + other.listed_by + "\")";
            throw UsageError(option_name(out.option) + ": expected a file that is not " +
                             (other.input ? "an input" : "another output") + ", got \"" + out.path + "\", the same file as " +
                             option_name(other.option) + " \"" + other.path + "\"" + listed + "; nothing was written");
        }
    }
}

}  // namespace

CLI::Option* input_files(CLI::Option* option) { return mark(option, kInputRole); }
CLI::Option* replaceable_input(CLI::Option* option) { return mark(option, kReplaceableRole); }
CLI::Option* output_file(CLI::Option* option) { return mark(option, kOutputRole); }

void check_command_line(CLI::App& command) {
    const std::vector<CLI::Option*> options = all_options(command);
    refuse_non_finite(options);
    refuse_outputs_naming_inputs(options);
}

void refuse_unless(const CLI::Option* option, bool applies, const std::string& when) {
    if (option->count() > 0 && !applies) throw UsageError(option_name(option) + ": only " + when);
}

}  // namespace vdbmesh::cli
