#include "work_limits.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common_options.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid_region.h"

namespace vdbmesh::cli {

namespace {

std::string number_text(double value) {
    std::ostringstream text;
    text.precision(3);
    text << value;
    return text.str();
}

std::string duration_text(double seconds) {
    if (seconds < 1e-3) return number_text(seconds * 1e6) + " us";
    if (seconds < 1) return number_text(seconds * 1e3) + " ms";
    if (seconds < 60) return number_text(seconds) + " s";
    if (seconds < 3600) return number_text(seconds / 60) + " min";
    return number_text(seconds / 3600) + (seconds == 3600 ? " hour" : " hours");
}

}  // namespace

void add_work_limit_option(CLI::App& command, WorkLimit& limit) {
    command.add_option("--work-limit", limit.minutes,
                       "Refuse a run whose work, estimated from the options before starting, exceeds this many minutes of one core")
        ->check(kFinitePositive)
        ->capture_default_str();
}

void refuse_beyond_work(const WorkLimit& limit, const std::string& option, double count, const std::string& units,
                        double seconds_each) {
    const double seconds = count * seconds_each, limit_seconds = 60 * limit.minutes;
    if (seconds <= limit_seconds) return;  // NaN too: the option checks refuse non-finite values first
    throw UsageError(option + ": expected at most " + duration_text(limit_seconds) + " of work on one core (--work-limit), got an estimate of " +
                     duration_text(seconds) + " (" + number_text(count) + " " + units + " at about " + duration_text(seconds_each) +
                     " each)");
}

void refuse_beyond_memory(const std::string& option, const std::string& what, double bytes) {
    constexpr double kGiB = 1024.0 * 1024 * 1024;
    if (bytes <= kMemoryLimitBytes) return;
    throw UsageError(option + ": expected at most " + number_text(kMemoryLimitBytes / kGiB) + " GiB of memory for " + what +
                     ", got an estimate of " + number_text(bytes / kGiB) + " GiB");
}

double MemoryLimit::bytes() const { return given() ? double(parse_memory_size("--memory", text)) : kMemoryLimitBytes; }

void add_memory_option(CLI::App& command, MemoryLimit& limit, const std::string& what) {
    command.add_option("--memory", limit.text,
                       "Refuse to start when the memory needed, estimated before starting from " + what +
                           ", exceeds SIZE (K, M, G: powers of 1024); the run then stays within about SIZE");
}

void refuse_beyond_memory(const MemoryLimit& limit, const std::string& option, const std::string& what, double bytes) {
    if (!limit.given()) return refuse_beyond_memory(option, what, bytes);
    const double needed = bytes + double(kProgramBytes), given = limit.bytes();
    if (needed <= given) return;
    constexpr double kMiB = 1024.0 * 1024;
    throw UsageError("--memory: expected at least " + std::to_string(std::uint64_t(std::ceil(needed / kMiB))) + "M for " + what +
                     " and the program, got " + limit.text + "; the smallest limit that could work is " +
                     std::to_string(std::uint64_t(std::ceil(needed / kMiB))) + "M");
}

double whole_grid_bytes(const GridRegionSource& source, bool converting) {
    const std::vector<NodeWeight> nodes = source.nodes();
    if (nodes.empty()) return 0;
    IndexBox box{nodes.front().origin, nodes.front().origin};
    for (const NodeWeight& node : nodes) {
        for (int a = 0; a < 3; ++a) {
            box.min[a] = std::min(box.min[a], node.origin[a]);
            box.max[a] = std::max(box.max[a], node.origin[a] + kNodeVoxels);
        }
    }
    return double(source.grid_bytes(box) + (converting ? source.opening_bytes() : 0));
}

}  // namespace vdbmesh::cli
