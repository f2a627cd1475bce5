#pragma once
// The exact crossing check of the hold-back, local (private to src/labels): every vertex stays
// within a voxel or two of its corner, so the triangles sit in a uniform grid of cells about
// two voxels wide and a triangle need only be tested against those sharing a cell with it.

#include <cstdint>
#include <vector>

#include "vdbmesh/mesh.h"

namespace vdbmesh::labels_detail {

/// Flags (per triangle) the triangles of @a subset (ascending) that are degenerate or meet
/// another triangle of @a mesh beyond the corners they share (detail::triangles_intersect(),
/// corners identified by index), and those other triangles. @a cell: the grid's cell size in
/// world units, at least the largest triangle's box.
std::vector<std::uint8_t> crossing_triangles(const Mesh& mesh, const std::vector<std::uint32_t>& subset, double cell);

}  // namespace vdbmesh::labels_detail
