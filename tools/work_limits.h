#pragma once
// Estimates, from the options alone (and an input's size), of the memory and work a run would
// take, checked before it starts (issue 32): a number that cannot finish is refused as a usage
// error naming the option, the estimate and the limit, rather than running for hours or ending
// in a bare std::bad_alloc. An estimate is a count (leaves, queries) times what one costs,
// measured with --threads 1 on the bench machine and rounded up; it bounds the order of
// magnitude, it is no prediction. The limits are fixed, so that a command is accepted or
// refused alike everywhere.

#include <string>

namespace vdbmesh::cli {

/// The memory a run may plan for, in bytes. `vdbmesh mesh --memory` (issue 28) is to set it per
/// run; until then every command uses this default.
inline constexpr double kMemoryLimitBytes = 16.0 * 1024 * 1024 * 1024;

/// The work a run may plan for: an hour of one core (less on several).
inline constexpr double kWorkLimitSeconds = 3600;

/// The most --threads: far beyond any machine's cores, short of what TBB cannot create.
inline constexpr int kMaxThreads = 1024;

/// Throws UsageError "OPTION: expected at most 1 hour of work, got an estimate of N hours
/// (COUNT UNITS at about S each)" when @a count units of @a seconds_each exceed kWorkLimitSeconds.
void refuse_beyond_work(const std::string& option, double count, const std::string& units, double seconds_each);

/// Throws UsageError naming @a option, the estimate and kMemoryLimitBytes in GiB when @a bytes
/// (of @a what) exceed it.
void refuse_beyond_memory(const std::string& option, const std::string& what, double bytes);

}  // namespace vdbmesh::cli
