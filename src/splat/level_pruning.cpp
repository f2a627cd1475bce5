// A splat tree built by region within a number of bytes (SplatOptions::max_bytes): the finest
// levels are pruned as the tree grows past it, instead of holding a tree the memory cannot.

#include <numeric>
#include <string>
#include <vector>

#include "splat/splat_build.h"
#include "vdbmesh/error.h"

namespace vdbmesh::splat {

// What kSplatBuildBytesPerNode counts: a node under construction, then, while the tree is laid
// out (breadth_first()), its SplatNode and its entries in the layout's order and first children.
static_assert(kSplatBuildBytesPerNode >=
              sizeof(BuildNode) + sizeof(SplatNode) + sizeof(std::pair<int, std::uint32_t>) + sizeof(std::uint32_t));

namespace {

std::uint64_t held_nodes(const Levels& levels) {
    return std::accumulate(levels.begin(), levels.end(), std::uint64_t(0),
                           [](std::uint64_t sum, const std::vector<BuildNode>& level) { return sum + level.size(); });
}

std::string mib(std::uint64_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"; }

}  // namespace

void LevelPruning::drop_below(Levels& levels, std::size_t from) {
    for (int level = 0; level < finest_kept_; ++level) std::vector<BuildNode>().swap(levels[level]);  // frees them
    std::vector<BuildNode>& finest = levels[finest_kept_];
    for (std::size_t i = from; i < finest.size(); ++i) {
        finest[i].first_child = 0;
        finest[i].child_count = 0;
    }
}

void LevelPruning::fit(Levels& levels) {
    if (max_bytes_ == 0) return;
    if (finest_kept_ > 0) drop_below(levels, childless_up_to_);
    while (held_nodes(levels) * kSplatBuildBytesPerNode > max_bytes_) {
        if (finest_kept_ == kSplatLeafLevel)
            throw Error("the splat tree needs more than the " + mib(max_bytes_) + " it may hold even with a splat per 8^3 cell (" +
                        std::to_string(held_nodes(levels)) + " nodes so far at " + std::to_string(kSplatBuildBytesPerNode) +
                        " bytes): give a larger --memory");
        ++finest_kept_;
        drop_below(levels, 0);
    }
    childless_up_to_ = levels[finest_kept_].size();
}

}  // namespace vdbmesh::splat
