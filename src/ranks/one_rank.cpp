// ranks.h without MPI (VDBMESH_MPI=OFF): one process, rank 0 of 1, or a rank of a simulated
// run (simulated_ranks.h).

#include "ranks/simulated_ranks.h"
#include "vdbmesh/ranks.h"

namespace vdbmesh {

RanksSession::RanksSession() = default;
RanksSession::~RanksSession() = default;

int this_rank() {
    const auto simulated = detail::simulated_rank();
    return simulated ? simulated->rank : 0;
}

int rank_count() {
    const auto simulated = detail::simulated_rank();
    return simulated ? simulated->ranks : 1;
}

void stream_to_rank0(const RankPart& mine, PartReceiver& receiver) {
    if (const auto simulated = detail::simulated_rank()) detail::simulated_stream(*simulated, mine, receiver);
}

std::optional<RankCollectives> ranks_collectives() { return std::nullopt; }

}  // namespace vdbmesh
