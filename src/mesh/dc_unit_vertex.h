#pragma once
// Private: the vertex of a unit cell of the dual error-0 mesh (docs/dmc.md, "Error 0"): the
// QEF minimiser of the cell's crossings, kept in the cell's box, then moved onto the trilinear
// isosurface of its 8 samples.

#include <array>

#include "mesh/edge_crossing.h"

namespace vdbmesh::detail {

/// How far (voxels) a unit cell's vertex stays inside its cell at error 0. Within this margin
/// every face test between two unit cells passes (the segment between their vertices crosses
/// their face inside it, both ends lying within the margin across), and round a grid edge the
/// four vertices' tetrahedra have volume at least 2 kUnitCellMargin^2 (above kOrientationFloor,
/// dc_polygons.cpp). A wider one keeps the quads rounder but the vertices farther from the
/// surface where it cuts a corner of the cell.
inline constexpr double kUnitCellMargin = 0.15;

/// The vertex, in local coordinates of the unit cell ([0, 1]^3), from @a start (the QEF
/// minimiser, local) clamped to [lo, hi] per axis, then Newton steps towards @a iso on the
/// trilinear interpolant of @a corner_values (corner c at (c & 1, (c >> 1) & 1, c >> 2)), each
/// clamped to the box. Where a value is not finite (beyond the scan box) the clamped start.
Point3d unit_cell_vertex(const std::array<double, 8>& corner_values, double iso, const Point3d& start, const Point3d& lo, const Point3d& hi);

}  // namespace vdbmesh::detail
