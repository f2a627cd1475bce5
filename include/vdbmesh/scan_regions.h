#pragma once
/// @file scan_regions.h
/// @brief A scan read by region straight from its file (issue 28): the conversion of grid.h
/// made once and kept, behind grid_region.h's interface.

#include <functional>
#include <memory>

#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/read.h"

namespace vdbmesh {

/// Opens a scan from its first slice.
using OpenSlices = std::function<std::unique_ptr<SliceReader>()>;

/// Whether a scan opened by region will be read (the survey then keeps its rows on disk), or
/// only described (nodes() and the estimates, for a memory check before a conversion).
enum class ScanRegionReads { by_region, none };

/// A scan read by region straight from its file (grid_region.h): every voxel inside a box read
/// has the value and state convert_to_grid() gives it (the same description and nodes too),
/// without the whole grid ever being held. Opening surveys the scan once (a conversion's time
/// and slice windows' memory): the sample range, which the background depends on, the active
/// voxels per node, and, unless @a reads is none, every row of leaves it makes, kept in a
/// temporary file ($TMPDIR; about the active leaves' samples, 2 bytes a value for 16-bit
/// scans). read() reads back the rows meeting its box, from any thread, in any order: the scan
/// file itself is read once. Throws as convert_to_grid() does, and Error when the temporary
/// file cannot be written.
std::unique_ptr<GridRegionSource> open_scan_regions(OpenSlices open, const ConvertOptions& options,
                                                    ScanRegionReads reads = ScanRegionReads::by_region);

}  // namespace vdbmesh
