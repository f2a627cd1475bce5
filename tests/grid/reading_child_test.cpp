// The limits of the child that reads an untrusted .vdb (src/grid/vdb_probe.h): a reader that
// loops is stopped by its CPU time, a child blocked without using CPU by the wall limit, and
// a read that is only slow (no CPU used while it waits: a starved or sleeping child) within
// the wall limit is not refused however long it takes beside its CPU limit.

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <string>

#include "grid/vdb_probe.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {
namespace {

constexpr std::uint64_t kAddressSpace = std::uint64_t{1} << 40;  // no memory limit that matters here

/// The FormatError's text when run_in_child() refuses @a reading, empty when it does not.
std::string refusal(const ChildReading& reading, const ChildLimits& limits) {
    try {
        run_in_child("reading-child-test.vdb", reading, limits);
    } catch (const FormatError& e) {
        return e.what();
    }
    return {};
}

TEST(ReadingChildTest, AChildSleepingPastTheWallLimitIsCaughtTwiceAndSaidToBeBlocked) {
    // 1 s of wall time a child, two children: about 2 s; the sleep (1000 s) never ends on its own.
    const std::string text = refusal([] { ::sleep(1000); }, {kAddressSpace, /*cpu_seconds=*/1000, /*wall_seconds=*/1});
    EXPECT_NE(text.find("reading-child-test.vdb"), std::string::npos) << text;
    EXPECT_NE(text.find("did not finish in 1 s, twice"), std::string::npos) << text;
    EXPECT_NE(text.find("blocked"), std::string::npos) << text;
}

TEST(ReadingChildTest, AChildLoopingIsStoppedByItsCpuTime) {
    // The wall limit (1000 s) is never reached: the loop's first CPU second ends it (SIGXCPU),
    // the child's CPU counted from the fork (RLIMIT_CPU counts whole seconds, so 1 to 2 s).
    const std::string text = refusal(
        [] {
            std::atomic<std::uint64_t> spins{0};
            for (;;) spins.fetch_add(1, std::memory_order_relaxed);
        },
        {kAddressSpace, /*cpu_seconds=*/1, /*wall_seconds=*/1000});
    EXPECT_NE(text.find("used more than 1 s of CPU time"), std::string::npos) << text;
}

TEST(ReadingChildTest, AReadSlowerThanItsCpuLimitButUsingNoCpuIsNotRefused) {
    // Session 19's refusal of a healthy file starved of the cores: 3 s of wall time beside a
    // CPU limit of 1 s; before the CPU limit, a limit of 1 s on the wall refused it.
    EXPECT_EQ(refusal([] { ::sleep(3); }, {kAddressSpace, /*cpu_seconds=*/1, /*wall_seconds=*/60}), "");
}

TEST(ReadingChildTest, TheLimitsAreCpuSecondsWithAMuchLongerWallLimit) {
    const unsigned topology_cpu = reading_cpu_seconds(std::uintmax_t{728'095'835} / 16);  // the tiled bunny's .vdb
    EXPECT_EQ(topology_cpu, 6u);
    EXPECT_GE(blocked_wall_seconds(topology_cpu), 10 * topology_cpu);
}

}  // namespace
}  // namespace vdbmesh::detail
