// select_solids(): --keep-largest and --min-component-volume on the grid, before meshing. The
// samples inside the object form a mask whose face-connected regions OpenVDB separates
// (tools::extractActiveVoxelSegmentMasks, largest first); the samples of the regions not kept
// are set to a value outside the object. Working on the grid keeps a solid's cavities with it
// (a cavity is only a surface component of the mesh, not a region of inside samples).
#include <openvdb/tools/LevelSetUtil.h>

#include <cmath>
#include <string>

#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_filter.h"

namespace vdbmesh {
namespace {

bool is_inside(double value, const MeshOptions& options) {
    return options.inside == Inside::above ? value > options.iso : value < options.iso;
}

/// Active where the sample is inside the object and in the scanned box.
openvdb::BoolGrid::Ptr inside_mask(const openvdb::FloatGrid& grid, const MeshOptions& options) {
    const std::optional<openvdb::CoordBBox> box = stored_scan_box(grid);
    const bool background_inside = is_inside(grid.background(), options);
    auto mask = openvdb::BoolGrid::create(false);
    if (background_inside) {
        if (!box) throw UsageError("selecting solids: the background is inside the object and the grid has no scanned box to bound it");
        mask->tree().fill(*box, true, true);
    }
    auto tile = grid.tree().cbeginValueAll();
    tile.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);  // tiles only
    for (; tile; ++tile) {
        const bool inside = is_inside(*tile, options);
        if (inside != background_inside) mask->tree().fill(tile.getBoundingBox(), inside, inside);
    }
    auto accessor = mask->getAccessor();
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
        for (auto voxel = leaf->cbeginValueAll(); voxel; ++voxel) {
            if (is_inside(*voxel, options)) {
                accessor.setValueOn(voxel.getCoord(), true);
            } else if (background_inside) {
                accessor.setValueOff(voxel.getCoord(), false);
            }
        }
    }
    if (box) mask->tree().clip(*box);
    return mask;
}

/// A value strictly outside the object: the background when it is, else its mirror image.
float outside_value(const openvdb::FloatGrid& grid, const MeshOptions& options) {
    const double background = grid.background();
    return float(is_inside(background, options) ? 2 * options.iso - background : background);
}

void set_outside(openvdb::FloatGrid& grid, const openvdb::BoolGrid& region, float outside) {
    auto accessor = grid.getAccessor();
    for (auto voxel = region.tree().cbeginValueOn(); voxel; ++voxel) {
        if (voxel.isVoxelValue()) {
            accessor.setValueOnly(voxel.getCoord(), outside);
        } else {
            grid.tree().fill(voxel.getBoundingBox(), outside, false);
        }
    }
}

}  // namespace

SolidSelectionReport select_solids(openvdb::FloatGrid& grid, const MeshOptions& options, const SolidSelection& selection) {
    if (!(selection.min_volume >= 0) || !std::isfinite(selection.min_volume)) {
        throw UsageError("minimum solid volume: expected a finite number >= 0, got " + std::to_string(selection.min_volume));
    }
    std::vector<openvdb::BoolGrid::Ptr> regions;
    openvdb::tools::extractActiveVoxelSegmentMasks(*inside_mask(grid, options), regions);  // largest first
    const double voxel_volume = grid.transform().voxelVolume();
    const float outside = outside_value(grid, options);
    SolidSelectionReport report;
    report.solids = regions.size();
    for (std::size_t i = 0; i < regions.size(); ++i) {
        const double volume = double(regions[i]->activeVoxelCount()) * voxel_volume;
        if ((selection.keep_largest && i > 0) || volume < selection.min_volume) {
            set_outside(grid, *regions[i], outside);
            ++report.dropped;
        }
    }
    return report;
}

}  // namespace vdbmesh
