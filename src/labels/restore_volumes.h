#pragma once
// Smoothing shrinks what is convex; this puts each label's volume back (private to src/labels).

#include <cstdint>
#include <vector>

#include "labels/smooth_sheets.h"

namespace vdbmesh::labels_detail {

/// Moves the vertices by the smallest displacement (in the least-squares sense, to first
/// order) that gives every meshed label the volume of its voxels (index space: one voxel is 1),
/// a few Newton steps: displacement = sum over labels of lambda_L times the gradient of label
/// L's volume, with the lambdas solving the (sparse, symmetric positive definite) Gram system.
/// @a voxels[value]: voxels of each label value (0 for labels not meshed, and the background).
/// Each vertex stays within @a max_offset of its corner.
void restore_volumes(std::vector<Point>& place, const SheetVertices& vertices, const std::vector<SheetQuad>& quads,
                     const std::vector<std::uint64_t>& voxels, double max_offset);

}  // namespace vdbmesh::labels_detail
