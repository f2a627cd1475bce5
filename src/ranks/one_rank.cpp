// ranks.h without MPI (VDBMESH_MPI=OFF): always one process, rank 0 of 1.

#include "vdbmesh/ranks.h"

namespace vdbmesh {

RanksSession::RanksSession() = default;
RanksSession::~RanksSession() = default;
int this_rank() { return 0; }
int rank_count() { return 1; }
std::vector<std::string> gather_to_rank0(const std::string& bytes) { return {bytes}; }

}  // namespace vdbmesh
