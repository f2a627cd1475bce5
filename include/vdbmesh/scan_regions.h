#pragma once
/// @file scan_regions.h
/// @brief A scan read by region straight from its file (issue 28): the conversion of grid.h
/// made a z-band at a time, behind grid_region.h's interface.

#include <functional>
#include <memory>

#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/read.h"

namespace vdbmesh {

/// Opens a scan from its first slice; called again when a read by region goes back in z.
using OpenSlices = std::function<std::unique_ptr<SliceReader>()>;

/// A scan read by region straight from its file (grid_region.h), in z-bands of leaf rows:
/// every voxel inside a box read has the value and state convert_to_grid() gives it (the same
/// description and nodes too), without the whole grid ever being held. Opening surveys the scan
/// once (a conversion's time, its slice windows' memory): the sample range, which the
/// background depends on, and the active voxels per node. read() makes the rows of leaves
/// meeting its box in z over the box's x-y rectangle widened by band + 1 (a band of a part of
/// the slices: only the part's rows are read, only the part converted) and keeps the last
/// band, so boxes of one x-y rectangle read in non-decreasing z (a column of bricks) read the
/// scan once; any other box reopens the scan. read() may be called from several threads (one
/// band is made at a time). Throws as convert_to_grid() does.
std::unique_ptr<GridRegionSource> open_scan_regions(OpenSlices open, const ConvertOptions& options);

}  // namespace vdbmesh
