#pragma once
/// @file ranks.h
/// @brief The processes of one run (issue 28): under `mpirun` with a build that has MPI
/// (VDBMESH_MPI=ON), MPI's ranks; otherwise one process, rank 0 of 1, and nothing changes.
/// Bricks go to ranks by a fixed rule from their weights alone (NodeWeight::active_voxels of
/// grid_region.h summed per brick), so every rank computes the same assignment without
/// talking; under MPI every rank then writes its own part of the output (RankCollectives),
/// while simulated ranks stream their parts to rank 0, which assembles it.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
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

/// The most bytes of another rank's part that rank 0 holds at once in stream_to_rank0(), and
/// that a sending rank holds to send (well under MPI's 2 GiB count limit).
inline constexpr std::size_t kPartPieceBytes = std::size_t{16} << 20;

/// A rank's part as stream_to_rank0() reads it: its size, and a reader of its bytes.
struct RankPart {
    std::uint64_t size = 0;
    /// Copies @a bytes bytes from @a offset into @a into (never past size).
    std::function<void(std::uint64_t offset, std::size_t bytes, char* into)> read;
};

/// What rank 0 does with the parts stream_to_rank0() brings: for ranks 1, 2, ... in order,
/// begin() with the part's size, then its bytes in order, a piece at a time.
class PartReceiver {
public:
    virtual ~PartReceiver() = default;
    virtual void begin(int rank, std::uint64_t size) = 0;
    virtual void piece(const char* bytes, std::size_t count) = 0;
};

/// Every other rank's part, streamed to rank 0 in rank order (a collective call: every rank
/// makes it): each rank above 0 reads its @a mine in pieces of at most kPartPieceBytes and sends
/// them; rank 0 hands them to @a receiver as they arrive, so that it never holds more than a
/// piece, whatever the parts' sizes (rank 0's own part is not read). One rank: nothing happens.
void stream_to_rank0(const RankPart& mine, PartReceiver& receiver);

/// What ranks that assemble the output together tell each other (collective calls: every rank
/// makes each, in the same order). A run over several processes that can talk (MPI) has them
/// (ranks_collectives()); one process, or ranks simulated one after another, has none.
struct RankCollectives {
    int rank = 0, ranks = 1;
    /// Every rank's bytes, in rank order, on every rank.
    std::function<std::vector<std::string>(const std::string& mine)> allgather;
    /// to_each[q] sent to rank q; returns what each rank sent this one, in rank order.
    std::function<std::vector<std::string>(const std::vector<std::string>& to_each)> exchange;
    /// The bitwise or over every rank of @a words (the same length on every rank), in place.
    std::function<void(std::vector<std::uint64_t>& words)> or_words;
    /// Rank 0's @a text, on every rank.
    std::function<std::string(const std::string& text)> from_rank0;
    /// Whether every rank passed true.
    std::function<bool(bool mine)> all;
    /// Not collective: sends @a bytes to rank @a to under @a tag and returns at once (the bytes
    /// are kept until taken); and the bytes rank @a from posted to this one under @a tag,
    /// waiting for them. One message per sender, receiver and tag.
    std::function<void(int to, int tag, std::string bytes)> post;
    std::function<std::string(int from, int tag)> take;
};

/// This run's collectives: MPI's under a launcher with more than one rank; none otherwise
/// (one process, or a simulated rank: those stream their parts to rank 0 instead).
std::optional<RankCollectives> ranks_collectives();

}  // namespace vdbmesh
