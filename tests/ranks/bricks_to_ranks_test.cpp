// The fixed rule that gives bricks to ranks (ranks.h): contiguous, balanced by weight, the same
// wherever it is computed; and one rank without a launcher.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <numeric>

#include "vdbmesh/error.h"
#include "vdbmesh/ranks.h"

namespace vdbmesh {
namespace {

/// The weight each rank takes.
std::vector<std::uint64_t> load_per_rank(const std::vector<std::uint64_t>& weights, const std::vector<int>& rank_of, int ranks) {
    std::vector<std::uint64_t> load(static_cast<std::size_t>(ranks), 0);
    for (std::size_t b = 0; b < weights.size(); ++b) load[static_cast<std::size_t>(rank_of[b])] += weights[b];
    return load;
}

TEST(BricksToRanksTest, OneRankTakesEverything) {
    EXPECT_EQ(bricks_to_ranks({5, 0, 7}, 1), (std::vector<int>{0, 0, 0}));
    EXPECT_TRUE(bricks_to_ranks({}, 4).empty());
}

TEST(BricksToRanksTest, EqualWeightsSplitEvenlyInOrder) {
    EXPECT_EQ(bricks_to_ranks(std::vector<std::uint64_t>(6, 10), 3), (std::vector<int>{0, 0, 1, 1, 2, 2}));
    EXPECT_EQ(bricks_to_ranks(std::vector<std::uint64_t>(4, 0), 2), (std::vector<int>{0, 0, 1, 1}));  // no weight: by count
}

TEST(BricksToRanksTest, RanksAreContiguousAndBalancedWithinTheHeaviestBrick) {
    // Weights like a scan's bricks: empty ones at the borders, heavy ones in the middle.
    std::vector<std::uint64_t> weights;
    for (int b = 0; b < 300; ++b) weights.push_back(static_cast<std::uint64_t>((b * 7919) % 1000) * (b % 13 == 0 ? 0 : 1) * (b > 40 && b < 250 ? 50 : 1));
    const std::uint64_t total = std::accumulate(weights.begin(), weights.end(), std::uint64_t{0});
    const std::uint64_t heaviest = *std::max_element(weights.begin(), weights.end());
    for (const int ranks : {2, 3, 7, 64}) {
        const std::vector<int> rank_of = bricks_to_ranks(weights, ranks);
        EXPECT_TRUE(std::is_sorted(rank_of.begin(), rank_of.end())) << ranks << " ranks";
        EXPECT_EQ(rank_of.front(), 0);
        EXPECT_LT(rank_of.back(), ranks);
        // Rank r's bricks have midpoints in [r, r + 1) * total / ranks: its load is within one
        // brick's weight of total / ranks.
        for (const std::uint64_t load : load_per_rank(weights, rank_of, ranks)) {
            EXPECT_LE(load, total / ranks + heaviest + 1) << ranks << " ranks";
            EXPECT_GE(load + heaviest + 1, total / ranks) << ranks << " ranks";
        }
    }
}

TEST(BricksToRanksTest, NoRanksIsAUsageError) { EXPECT_THROW(bricks_to_ranks({1}, 0), UsageError); }

TEST(RanksTest, WithoutALauncherThereIsOneRank) {
    if (started_by_mpi_launcher()) GTEST_SKIP() << "started by an MPI launcher";
    const RanksSession session;
    EXPECT_EQ(this_rank(), 0);
    EXPECT_EQ(rank_count(), 1);
    // One rank: its own part is never read and nothing is received.
    struct Refusing final : PartReceiver {
        void begin(int, std::uint64_t) override { ADD_FAILURE() << "a part was received"; }
        void piece(const char*, std::size_t) override { ADD_FAILURE() << "a piece was received"; }
    } receiver;
    RankPart mine{5, [](std::uint64_t, std::size_t, char*) { ADD_FAILURE() << "rank 0's part was read"; }};
    stream_to_rank0(mine, receiver);
}

}  // namespace
}  // namespace vdbmesh
