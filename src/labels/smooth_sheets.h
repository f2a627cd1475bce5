#pragma once
// Placing the vertices of the multi-label surface (private to src/labels).

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "vdbmesh/labels.h"

namespace vdbmesh::labels_detail {

using Point = std::array<double, 3>;

/// Per vertex (index space: voxel centres at integers) its unsmoothed place and its corner.
struct SheetVertices {
    std::vector<Point> base;
    std::vector<Point> corner;
};

/// A wall: four vertices counter-clockwise seen from sides[1], whose label is on the high side.
struct SheetQuad {
    std::array<std::uint32_t, 4> vertex;
    std::array<std::uint16_t, 2> sides;  ///< {low voxel's label, high voxel's label}
};

/// Smooths the vertices (options.smoothing_iterations Jacobi passes of the mean of their
/// neighbours along the walls, each kept within options.max_offset of its corner), gives each
/// label back the volume of its @a voxels (restore_volumes.h), splits each
/// quad along its shorter diagonal, maps to world by @a index_to_world (winding reversed for a
/// mirroring map, so normals still point from sides[0] to sides[1]), then holds back vertices
/// toward their unsmoothed place, halving their move, where a triangle crosses another or
/// degenerates (crossing_check.h: exact predicates); the free vertices near the held ones
/// then make up the volume those lost, and the check goes on over the triangles that moved.
/// Fills out.mesh, out.sides and out.vertices_held_back. Throws Error if the unsmoothed
/// surface itself is not clean.
void smooth_sheets(const SheetVertices& vertices, const std::vector<SheetQuad>& quads, const std::vector<std::uint64_t>& voxels,
                   const LabelMeshOptions& options,
                   const Affine& index_to_world, LabelSurface& out, const std::function<void(double)>& progress);

}  // namespace vdbmesh::labels_detail
