// Run by ctest under mpirun with 1, 2 and 3 ranks (VDBMESH_MPI=ON): each rank computes the same
// brick-to-rank assignment and sends rank 0 the bricks it took and a buffer of its own (sizes
// differ per rank, rank 0's is empty; none reaches the 1 GiB piece size, too big for a test);
// rank 0 checks what it gathered. Exit status 0 when every check holds.

#include <cstdio>
#include <string>
#include <vector>

#include "vdbmesh/ranks.h"

namespace {

/// Rank r's buffer: r * 100,000 bytes (rank 0 none), each byte a function of rank and position.
std::string buffer_of(int rank) {
    std::string bytes(static_cast<std::size_t>(rank) * 100000, '\0');
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>((i * 31 + static_cast<std::size_t>(rank) * 7) & 0xFF);
    return bytes;
}

}  // namespace

int main(int argc, char** argv) {
    const vdbmesh::RanksSession session;
    const int rank = vdbmesh::this_rank(), ranks = vdbmesh::rank_count();
    const int expected_ranks = argc > 1 ? std::stoi(argv[1]) : ranks;
    if (ranks != expected_ranks || !vdbmesh::started_by_mpi_launcher()) {
        std::fprintf(stderr, "rank %d: %d ranks, expected %d under a launcher\n", rank, ranks, expected_ranks);
        return 1;
    }
    // Every rank takes its bricks from the same rule; rank 0 checks that the bricks each rank
    // reports as its own are exactly the rule's.
    const std::vector<std::uint64_t> weights{3, 0, 9, 4, 4, 12, 1, 0, 6, 2};
    const std::vector<int> rank_of = vdbmesh::bricks_to_ranks(weights, ranks);
    std::string mine;
    for (std::size_t b = 0; b < weights.size(); ++b)
        if (rank_of[b] == rank) mine += static_cast<char>('a' + b);
    const std::vector<std::string> bricks = vdbmesh::gather_to_rank0(mine);
    const std::vector<std::string> buffers = vdbmesh::gather_to_rank0(buffer_of(rank));
    if (rank != 0) return bricks.empty() && buffers.empty() ? 0 : 1;
    int failures = 0;
    std::string all_bricks;
    for (int r = 0; r < ranks; ++r) {
        all_bricks += bricks[static_cast<std::size_t>(r)];
        if (buffers[static_cast<std::size_t>(r)] != buffer_of(r)) {
            std::fprintf(stderr, "rank %d's buffer arrived changed (%zu bytes)\n", r, buffers[static_cast<std::size_t>(r)].size());
            ++failures;
        }
    }
    if (all_bricks != "abcdefghij") {
        std::fprintf(stderr, "bricks by rank in rank order: %s, expected every brick once, in order\n", all_bricks.c_str());
        ++failures;
    }
    return failures == 0 ? 0 : 1;
}
