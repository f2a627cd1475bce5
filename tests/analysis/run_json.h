#pragma once
// Shared by the measure and section CLI tests: a subcommand run with --json, its stdout parsed.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli.h"

namespace vdbmesh::test {

/// Runs `vdbmesh args...`, its exit status into @a status; its stdout parsed as JSON when it
/// succeeded, else null.
inline nlohmann::json run_json(const std::vector<std::string>& args, int& status) {
    testing::internal::CaptureStdout();
    status = cli::run(args);
    const std::string out = testing::internal::GetCapturedStdout();
    return status == cli::kSuccess ? nlohmann::json::parse(out) : nlohmann::json();
}

}  // namespace vdbmesh::test
