#pragma once
// The checks every subcommand's command line passes after parsing and before any work (issue
// 32), in one place rather than a case per command:
//  - no option's value is NaN or infinite (nor too large for a double), whole or as one item of
//    a list: a number option that means "a finite number" everywhere;
//  - no output file names an input, nor another output: the same file by device and inode,
//    through symbolic and hard links; the scans a .conf range-scan set lists are inputs too. An
//    input marked replaceable may be named by the output (`process x.vdb -o x.vdb`), as the
//    atomic writer replaces it only once the run succeeded.
// Failures are UsageErrors (exit 2) naming the option.

#include <CLI/CLI.hpp>
#include <string>
#include <utility>

namespace vdbmesh::cli {

/// Marks an option (a positional too) whose values name files read by the command.
CLI::Option* input_files(CLI::Option* option);
/// Marks an input that the output may name: it is then replaced (atomically, on success).
CLI::Option* replaceable_input(CLI::Option* option);
/// Marks an option that names a file the command writes.
CLI::Option* output_file(CLI::Option* option);

/// Runs the checks above on @a command's options given; throws UsageError.
void check_command_line(CLI::App& command);

/// A subcommand that runs check_command_line() on itself before its callback, so that no
/// command can skip it.
class CheckedCommand : public CLI::App {
public:
    CheckedCommand(std::string summary, std::string name, CLI::App* parent)
        : CLI::App(std::move(summary), std::move(name), parent) {}

protected:
    void pre_callback() override { check_command_line(*this); }
};

/// Throws UsageError "OPTION: only WHEN" when @a option was given though it does not apply
/// (@a applies false): an option that would be silently ignored is refused instead.
void refuse_unless(const CLI::Option* option, bool applies, const std::string& when);

}  // namespace vdbmesh::cli
