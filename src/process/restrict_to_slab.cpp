// restrict_to_slab(): a sub-range of slices (shared seed 001 meshes one slab of slices at a time),
// by cutting the scanned box, beyond which the meshers see only outside.
#include <algorithm>
#include <string>

#include "process/store_scan_box.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid_filter.h"

namespace vdbmesh {

void restrict_to_slab(openvdb::FloatGrid& grid, int axis, int first, int last) {
    if (axis < 0 || axis > 2) throw UsageError("slab axis: expected 0, 1 or 2, got " + std::to_string(axis));
    if (first > last) throw UsageError("slab: expected FIRST <= LAST, got " + std::to_string(first) + ":" + std::to_string(last));
    openvdb::CoordBBox box;
    if (const auto scanned = stored_scan_box(grid)) {
        box = *scanned;
    } else {
        grid.tree().evalLeafBoundingBox(box);
    }
    const std::string axis_name(1, char('x' + axis));
    if (last < box.min()[axis] || first > box.max()[axis]) {
        throw UsageError("slab " + axis_name + "=" + std::to_string(first) + ":" + std::to_string(last) +
                         ": expected slices overlapping the scan's " + std::to_string(box.min()[axis]) + ":" +
                         std::to_string(box.max()[axis]));
    }
    box.min()[axis] = std::max(box.min()[axis], first);
    box.max()[axis] = std::min(box.max()[axis], last);
    detail::store_scan_box(grid, box);
}

}  // namespace vdbmesh
