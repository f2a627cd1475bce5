#pragma once
// Estimates, from the options alone (and an input's size), of the memory and work a run would
// take, checked before it starts (issue 32): a number that cannot finish soon is refused as a
// usage error naming the option, the estimate and the limit, rather than running for many
// minutes or ending in a bare std::bad_alloc. An estimate is a count (leaves, queries) times
// what one costs, measured with --threads 1 on the bench machine and rounded up; it bounds the
// order of magnitude, it is no prediction. One rule for every command that estimates its work:
// 2 minutes of one core unless the run's --work-limit says more, 16 GiB of memory.

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

#include "vdbmesh/program_memory.h"

namespace vdbmesh {
class GridRegionSource;
}

namespace vdbmesh::cli {

/// The memory a run may plan for, in bytes, unless its --memory says otherwise (issue 28).
inline constexpr double kMemoryLimitBytes = 16.0 * 1024 * 1024 * 1024;

/// A float leaf of an OpenVDB tree in memory: its 512 values (a buffer of their own) and the
/// node (masks, origin, the buffer's pointer), about 100 bytes.
inline constexpr double kFloatLeafBytes = 512 * 4 + 100;

/// The work a run may plan for unless --work-limit says more: 2 minutes of one core (1 on two).
/// A command that would take longer on an ordinary laptop is more likely a mistyped number
/// (`lattice --band 1000`, about 2.4 minutes) than a wish; the flagship lattice of the README
/// (6000^3 voxels, periodic) is estimated at 45 s.
inline constexpr double kDefaultWorkLimitSeconds = 120;

/// The most --threads: far beyond any machine's cores, short of what TBB cannot create.
inline constexpr int kMaxThreads = 1024;

/// The work limit of one run.
struct WorkLimit {
    double minutes = kDefaultWorkLimitSeconds / 60;
};

/// --work-limit MINUTES, for the commands that estimate their work (and only those: elsewhere it
/// would be an option that does nothing).
void add_work_limit_option(CLI::App& command, WorkLimit& limit);

/// Throws UsageError "OPTION: expected at most 2 min of work on one core (--work-limit), got an
/// estimate of N min (COUNT UNITS at about S each)" when @a count units of @a seconds_each
/// exceed @a limit.
void refuse_beyond_work(const WorkLimit& limit, const std::string& option, double count, const std::string& units,
                        double seconds_each);

/// Throws UsageError naming @a option, the estimate and kMemoryLimitBytes in GiB when @a bytes
/// (of @a what) exceed it.
void refuse_beyond_memory(const std::string& option, const std::string& what, double bytes);

/// --memory SIZE of a command that cannot bound its work to any size (it needs the whole grid
/// or mesh) and estimates its need before starting instead: a limit under the estimate is
/// refused, one above it held to by the estimate's margin.
struct MemoryLimit {
    std::string text;  ///< as given; empty: kMemoryLimitBytes, the default plan
    bool given() const { return !text.empty(); }
    /// The limit in bytes (parse_memory_size()).
    double bytes() const;
};

/// --memory SIZE; @a what says what the estimate covers.
void add_memory_option(CLI::App& command, MemoryLimit& limit, const std::string& what);

/// With --memory given: throws UsageError "--memory: expected at least X for WHAT, got Y" when
/// the estimate @a bytes (with vdbmesh::kProgramBytes added) exceeds it; without it,
/// refuse_beyond_memory(@a option, @a what, @a bytes).
void refuse_beyond_memory(const MemoryLimit& limit, const std::string& option, const std::string& what, double bytes);

/// The whole grid of @a source: the bytes read() of its every node would hold (its
/// grid_bytes(); with @a converting, opening_bytes() too: a conversion holds the converter's
/// windows beside the grid it makes), from the tree's topology (a .vdb's, a scan's survey)
/// without reading a voxel.
double whole_grid_bytes(const GridRegionSource& source, bool converting = false);

}  // namespace vdbmesh::cli
