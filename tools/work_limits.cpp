#include "work_limits.h"

#include <sstream>

#include "common_options.h"
#include "vdbmesh/error.h"

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

}  // namespace vdbmesh::cli
