#pragma once
// The command-line program as a function, so tests can run it in-process.

#include <string>
#include <vector>

namespace vdbmesh::cli {

/// Exit statuses of the program.
enum ExitStatus : int { kSuccess = 0, kRuntimeError = 1, kUsageError = 2, kCheckFailed = 3 };

/// Runs `vdbmesh args...` (args excludes the program name); messages go to stderr.
int run(const std::vector<std::string>& args);

}  // namespace vdbmesh::cli
