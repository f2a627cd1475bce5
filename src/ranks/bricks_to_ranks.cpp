// The fixed rule of ranks.h: contiguous runs of bricks by their weight's midpoint.

#include <cstdlib>
#include <numeric>
#include <string>

#include "vdbmesh/error.h"
#include "vdbmesh/ranks.h"

namespace vdbmesh {

std::vector<int> bricks_to_ranks(const std::vector<std::uint64_t>& weights, int ranks) {
    if (ranks < 1) throw UsageError("ranks: expected at least 1, got " + std::to_string(ranks));
    std::vector<std::uint64_t> counted = weights;
    const bool weightless = std::accumulate(weights.begin(), weights.end(), std::uint64_t{0}) == 0;
    if (weightless) counted.assign(weights.size(), 1);
    // Twice the weights, so that the midpoints are integers: exact, the same on every rank.
    const unsigned __int128 total = 2 * static_cast<unsigned __int128>(std::accumulate(counted.begin(), counted.end(), std::uint64_t{0}));
    std::vector<int> rank_of(weights.size(), 0);
    unsigned __int128 before = 0;
    for (std::size_t b = 0; b < counted.size(); ++b) {
        const unsigned __int128 midpoint = before + counted[b];  // (2 * before + 2 * weight / 2)
        rank_of[b] = static_cast<int>(midpoint * static_cast<unsigned>(ranks) / total);
        if (rank_of[b] >= ranks) rank_of[b] = ranks - 1;
        before += 2 * static_cast<unsigned __int128>(counted[b]);
    }
    return rank_of;
}

bool started_by_mpi_launcher() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
        if (const char* value = std::getenv(name); value && *value) return true;
    return false;
}

}  // namespace vdbmesh
