// `view --memory SIZE`: how SIZE is shared between what the grid holds once opened, the splat
// tree, one close-up's read and the page (view.h, ViewMemoryPlan).

#include <algorithm>

#include "vdbmesh/program_memory.h"
#include "vdbmesh/splats.h"
#include "vdbmesh/view.h"

namespace vdbmesh {

std::uint64_t ViewMemoryPlan::rest() const { return limit > kProgramBytes ? limit - kProgramBytes : 0; }

std::uint64_t ViewMemoryPlan::smallest_limit() { return kProgramBytes + 4 * kMinCloseUpBytes; }

std::uint64_t ViewMemoryPlan::close_up_bytes() const { return rest() / 4; }

std::uint64_t ViewMemoryPlan::splat_tree_bytes(std::uint64_t opened) const {
    const std::uint64_t r = rest();
    if (2 * opened >= r) return 0;
    const std::uint64_t building = r - opened;  // nothing else runs while the tree is fitted
    const std::uint64_t kept_nodes = (r / 2 - opened) / sizeof(SplatNode);  // the tree once fitted, beside the page's shares
    return std::min(building, kept_nodes * kSplatBuildBytesPerNode);
}

std::uint64_t ViewMemoryPlan::smallest_limit(std::uint64_t opened, std::uint64_t tree_bytes) {
    const std::uint64_t tree_nodes = (tree_bytes + kSplatBuildBytesPerNode - 1) / kSplatBuildBytesPerNode;
    const std::uint64_t r = std::max({4 * kMinCloseUpBytes, opened + tree_bytes, 2 * (opened + tree_nodes * sizeof(SplatNode))});
    return kProgramBytes + r;
}

}  // namespace vdbmesh
