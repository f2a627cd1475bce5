// `view --memory SIZE`: how SIZE is shared (ViewMemoryPlan), judged by the bounds it promises
// (the tree's build within what the opened grid leaves, the fitted tree within half of it
// beside the page's and a close-up's quarters) and by its smallest limits being the smallest.

#include <gtest/gtest.h>

#include <cstdint>

#include "vdbmesh/program_memory.h"
#include "vdbmesh/splats.h"
#include "vdbmesh/view.h"

namespace vdbmesh {
namespace {

constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;

/// What the plan promises for @a opened bytes: the build within the rest beside them, the
/// fitted tree (sizeof(SplatNode) a node) and what is opened within half the rest, and the
/// close-up's and the page's quarters beside them.
void expect_within(const ViewMemoryPlan& plan, std::uint64_t opened) {
    const std::uint64_t rest = plan.limit - kProgramBytes;
    const std::uint64_t tree = plan.splat_tree_bytes(opened);
    if (tree == 0) return;  // nothing left: refused (the caller names the smallest limit)
    EXPECT_LE(opened + tree, rest) << plan.limit << " " << opened;
    EXPECT_LE(opened + tree / kSplatBuildBytesPerNode * sizeof(SplatNode) + 2 * plan.close_up_bytes(), rest) << plan.limit << " " << opened;
}

TEST(ViewMemoryPlan, SharesStayWithinTheLimit) {
    for (std::uint64_t limit : {320 * kMiB, 1024 * kMiB, 2048 * kMiB, 4096 * kMiB})
        for (std::uint64_t opened : {std::uint64_t(0), 10 * kMiB, 100 * kMiB, 300 * kMiB, 2000 * kMiB}) {
            const ViewMemoryPlan plan{limit};
            expect_within(plan, opened);
            EXPECT_EQ(plan.close_up_bytes(), (limit - kProgramBytes) / 4);
        }
    EXPECT_EQ(ViewMemoryPlan{1024 * kMiB}.splat_tree_bytes(600 * kMiB), 0u);  // opened past half the rest: nothing left
}

/// The smallest limit named in a refusal holds the tree asked for; a mebibyte less does not.
TEST(ViewMemoryPlan, TheSmallestLimitIsTheSmallestThatHoldsTheTree) {
    EXPECT_EQ(ViewMemoryPlan::smallest_limit(), kProgramBytes + 4 * ViewMemoryPlan::kMinCloseUpBytes);
    for (std::uint64_t opened : {std::uint64_t(0), 5 * kMiB, 150 * kMiB, 700 * kMiB})
        for (std::uint64_t tree : {kMiB, 90 * kMiB, 1000 * kMiB}) {
            const std::uint64_t smallest = ViewMemoryPlan::smallest_limit(opened, tree);
            EXPECT_GE(ViewMemoryPlan{smallest}.splat_tree_bytes(opened), tree) << opened << " " << tree;
            if (smallest > ViewMemoryPlan::smallest_limit())
                EXPECT_LT(ViewMemoryPlan{smallest - kMiB}.splat_tree_bytes(opened), tree) << opened << " " << tree;
        }
}

}  // namespace
}  // namespace vdbmesh
