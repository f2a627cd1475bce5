#pragma once
// Flags shared by several subcommands, and the progress line on stderr.

#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>

#include "vdbmesh/read.h"

namespace vdbmesh::cli {

/// --threads and --quiet.
struct CommonOptions {
    int threads = 0;  ///< 0: all cores
    bool quiet = false;
};
void add_common_options(CLI::App& command, CommonOptions& options);

/// Limits TBB to options.threads while alive (no limit when 0).
class ThreadLimit {
public:
    explicit ThreadLimit(const CommonOptions& options);
    ~ThreadLimit();

private:
    std::unique_ptr<tbb::global_control> control_;
};

/// --raw-dims, --raw-type, --raw-endian, --spacing, --header-bytes, as strings until parsed.
struct ReadFlags {
    std::string raw_dims, raw_type = "u8", raw_endian = "little", spacing;
    std::int64_t header_bytes = 0;  ///< signed, so that a negative value is reported as given
    bool allow_outside_data = false;
    /// The options that mean something only with --raw-dims (set by add_read_flags): given
    /// without it, they are refused rather than ignored.
    std::vector<const CLI::Option*> raw_only;
    /// All of these flags (set by add_read_flags): given with a mesh input, they are refused.
    std::vector<const CLI::Option*> scan_only;
    /// Throws UsageError naming the first of these flags given, for the mesh file @a mesh.
    void refuse_for_mesh(const std::string& mesh) const;
    /// Converts to ReadOptions; throws UsageError on malformed values. @a more_inputs are the
    /// positional inputs after the first: the further parts of a split raw scan, read in order
    /// (ReadOptions::raw_more_files), allowed only with --raw-dims.
    ReadOptions to_read_options(const std::vector<std::string>& more_inputs = {}) const;
};
void add_read_flags(CLI::App& command, ReadFlags& flags);

/// Accepts a finite number >= 0 (CLI11's NonNegativeNumber lets nan through, and prints DBL_MAX
/// in 309 digits in its message).
inline const CLI::Validator kFiniteNonNegative(
    [](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !std::isfinite(value) || value < 0)
            return "expected a finite number >= 0, got " + text;
        return {};
    },
    "FINITE >= 0");

/// Accepts a finite number > 0 (CLI11's PositiveNumber prints DBL_MAX in 309 digits in its message).
inline const CLI::Validator kFinitePositive(
    [](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !std::isfinite(value) || value <= 0)
            return "expected a finite number > 0, got " + text;
        return {};
    },
    "FINITE > 0");

/// A one-line percentage on stderr, shown only on a terminal and without --quiet.
class Progress {
public:
    Progress(std::string label, bool quiet);
    ~Progress();
    void operator()(double fraction);

private:
    std::string label_;
    bool enabled_;
    int last_percent_ = -1;
};

/// Parses "a,b,c" into numbers; throws UsageError naming @a flag.
std::vector<double> parse_number_list(const std::string& flag, const std::string& text);

/// Parses a size in bytes as @a flag takes it: a whole number with an optional suffix K, M or
/// G (powers of 1024, any case), at least 1M; throws UsageError naming @a flag otherwise.
std::uint64_t parse_memory_size(const std::string& flag, const std::string& text);

}  // namespace vdbmesh::cli
