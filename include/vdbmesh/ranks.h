#pragma once
/// @file ranks.h
/// @brief The processes of one run (issue 28): under `mpirun` with a build that has MPI
/// (VDBMESH_MPI=ON), MPI's ranks; otherwise one process, rank 0 of 1, and nothing changes.
/// Bricks go to ranks by a fixed rule from their weights alone (NodeWeight::active_voxels of
/// grid_region.h summed per brick), so every rank computes the same assignment without
/// talking; rank 0 gathers the others' bytes to assemble the output.

#include <cstdint>
#include <string>
#include <vector>

namespace vdbmesh {

/// The rank of each brick, bricks given in their (z-major) visiting order: contiguous runs, rank
/// r taking the bricks whose weight prefix (the sum of the weights before a brick plus half its
/// own) falls in [r * total / ranks, (r + 1) * total / ranks). Contiguous, so that each rank reads
/// one z-range of a scan; by the midpoint, so that a heavy brick goes where most of it lies.
/// Non-decreasing in the brick index; with no weight at all, by count. @a ranks >= 1.
std::vector<int> bricks_to_ranks(const std::vector<std::uint64_t>& weights, int ranks);

/// Whether this process was started by an MPI launcher (mpirun, srun: OMPI_COMM_WORLD_SIZE,
/// PMI_SIZE or PMIX_RANK in the environment).
bool started_by_mpi_launcher();

/// MPI for the life of the object when started by a launcher in a build with MPI (MPI_Init,
/// then MPI_Finalize); nothing otherwise. One per program, in main().
class RanksSession {
public:
    RanksSession();
    ~RanksSession();
    RanksSession(const RanksSession&) = delete;
    RanksSession& operator=(const RanksSession&) = delete;
};

/// This process's rank and the number of ranks: 0 and 1 without a live RanksSession under MPI.
int this_rank();
int rank_count();

/// Every rank's @a bytes, in rank order, on rank 0 (empty elsewhere): a collective call, every
/// rank must make it. Any size (sent in pieces under MPI's 2 GiB count limit).
std::vector<std::string> gather_to_rank0(const std::string& bytes);

}  // namespace vdbmesh
