// subsample_grid(): every step-th sample (shared seed 001 steps coarser over the grid). Tiles are
// carried over as filled regions, then the kept samples of every leaf are copied.
#include <cmath>
#include <tuple>
#include <string>

#include "process/store_scan_box.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid_filter.h"

namespace vdbmesh {
namespace {

/// The indices i with step * i in [lo, hi].
std::pair<int, int> kept_range(int lo, int hi, int step) {
    return {int(std::ceil(double(lo) / step)), int(std::floor(double(hi) / step))};
}

openvdb::CoordBBox kept_box(const openvdb::CoordBBox& box, int step) {
    openvdb::CoordBBox kept;
    for (int a = 0; a < 3; ++a) std::tie(kept.min()[a], kept.max()[a]) = kept_range(box.min()[a], box.max()[a], step);
    return kept;
}

bool is_empty(const openvdb::CoordBBox& box) {
    return box.min().x() > box.max().x() || box.min().y() > box.max().y() || box.min().z() > box.max().z();
}

}  // namespace

std::shared_ptr<openvdb::FloatGrid> subsample_grid(const openvdb::FloatGrid& grid, int step) {
    if (step < 1) throw UsageError("step: expected a whole number >= 1, got " + std::to_string(step));
    openvdb::FloatGrid::Ptr result = openvdb::gridPtrCast<openvdb::FloatGrid>(grid.copyGridWithNewTree());
    result->setTransform(grid.transform().copy());
    result->transform().preScale(double(step));
    auto tile = grid.tree().cbeginValueAll();
    tile.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);  // tiles only
    for (; tile; ++tile) {
        const openvdb::CoordBBox kept = kept_box(tile.getBoundingBox(), step);
        if (!is_empty(kept)) result->tree().fill(kept, *tile, tile.isValueOn());
    }
    auto accessor = result->getAccessor();
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
        const openvdb::CoordBBox kept = kept_box(leaf->getNodeBoundingBox(), step);
        for (auto ijk = kept.begin(); ijk; ++ijk) {
            const openvdb::Coord source((*ijk).x() * step, (*ijk).y() * step, (*ijk).z() * step);
            accessor.setValueOnly(*ijk, leaf->getValue(source));
            accessor.setActiveState(*ijk, leaf->isValueOn(source));
        }
    }
    if (const auto box = stored_scan_box(grid)) detail::store_scan_box(*result, kept_box(*box, step));
    return result;
}

}  // namespace vdbmesh
