// Run by ctest under mpirun with 1, 2 and 3 ranks (VDBMESH_MPI=ON): each rank computes the same
// brick-to-rank assignment and streams rank 0 the bricks it took, then a part of its own (sizes
// differ per rank: rank 1's fits in one piece, rank 2's takes two and a bit); rank 0 checks what
// it received, and that it never received more than a piece at once. Exit status 0 when every
// check holds.

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "vdbmesh/ranks.h"

namespace {

/// Rank r's part: (r - 1) * 2.2 pieces and 1,000 bytes (rank 0's is never read), each byte a
/// function of rank and position.
std::string part_of(int rank) {
    const std::size_t size = rank == 0 ? 0 : std::size_t((rank - 1) * 2.2 * double(vdbmesh::kPartPieceBytes)) + 1000;
    std::string bytes(size, '\0');
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>((i * 31 + static_cast<std::size_t>(rank) * 7) & 0xFF);
    return bytes;
}

vdbmesh::RankPart as_part(const std::string& bytes) {
    return {bytes.size(), [&bytes](std::uint64_t offset, std::size_t count, char* into) { bytes.copy(into, count, offset); }};
}

/// Rank 0's side: every part as received, in rank order, and the largest piece.
struct Received final : vdbmesh::PartReceiver {
    void begin(int rank, std::uint64_t size) override {
        ranks.push_back(rank);
        sizes.push_back(size);
        parts.emplace_back();
    }
    void piece(const char* bytes, std::size_t count) override {
        parts.back().append(bytes, count);
        largest_piece = std::max(largest_piece, count);
    }
    std::vector<int> ranks;
    std::vector<std::uint64_t> sizes;
    std::vector<std::string> parts;
    std::size_t largest_piece = 0;
};

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
    Received bricks, parts;
    vdbmesh::stream_to_rank0(as_part(mine), bricks);
    const std::string own = part_of(rank);
    vdbmesh::stream_to_rank0(as_part(own), parts);
    if (rank != 0) return bricks.parts.empty() && parts.parts.empty() ? 0 : 1;
    int failures = 0;
    std::string all_bricks = mine;
    for (const std::string& theirs : bricks.parts) all_bricks += theirs;
    for (int r = 1; r < ranks; ++r) {
        const std::size_t at = std::size_t(r - 1);
        if (parts.ranks.size() <= at || parts.ranks[at] != r || parts.sizes[at] != part_of(r).size() || parts.parts[at] != part_of(r)) {
            std::fprintf(stderr, "rank %d's part did not arrive whole, in rank order\n", r);
            ++failures;
        }
    }
    if (parts.parts.size() != std::size_t(ranks - 1) || parts.largest_piece > vdbmesh::kPartPieceBytes) {
        std::fprintf(stderr, "%zu parts received for %d ranks, the largest piece %zu bytes\n", parts.parts.size(), ranks, parts.largest_piece);
        ++failures;
    }
    if (all_bricks != "abcdefghij") {
        std::fprintf(stderr, "bricks by rank in rank order: %s, expected every brick once, in order\n", all_bricks.c_str());
        ++failures;
    }
    return failures == 0 ? 0 : 1;
}
