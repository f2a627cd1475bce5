#pragma once
// Private: N ranks simulated by N plain processes run one after another (docs/scale.md, "64
// ranks simulated"): VDBMESH_SIMULATE_RANKS="R/N:FOLDER" makes this process rank R of N; its
// gather writes its bytes to FOLDER/part-R, and rank 0's reads every other rank's part from
// there, so ranks N-1 .. 1 run first. Each process's peak memory and the bytes it would send
// are then measured one rank at a time, on one machine.

#include <filesystem>
#include <optional>
#include <string>

#include "vdbmesh/ranks.h"

namespace vdbmesh::detail {

struct SimulatedRank {
    int rank = 0, ranks = 1;
    std::filesystem::path folder;
};

/// The simulated rank VDBMESH_SIMULATE_RANKS names, if set. @throw UsageError when malformed.
std::optional<SimulatedRank> simulated_rank();

/// stream_to_rank0() for a simulated rank: rank 0 receives every other part in rank order.
/// @throw Error when a part cannot be written or read (a rank above 0 has not run).
void simulated_stream(const SimulatedRank& simulated, const RankPart& mine, PartReceiver& receiver);

}  // namespace vdbmesh::detail
