#pragma once
// inside="auto": which side of the level is the object, decided on the grid itself, the same
// way for arrays and for files.

#include "array_slice_reader.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::python {

/// The side of @a level that touches less of the border of the grid's scanned box (its
/// samples on the box's six faces; samples at the level count for neither side; a tie gives
/// above, the CT convention): a level set's negative inside, a CT's dense material, not their
/// complement. A grid that records no box (a .vdb not made by convert): below for a level
/// set, else the side away from the background, which fills the space beyond the data.
Inside inside_away_from_border(const openvdb::FloatGrid& grid, double level);

/// The same for an array, on its own samples (its six faces), before any conversion.
Inside inside_away_from_border(const StridedVolume& volume, double level);

}  // namespace vdbmesh::python
