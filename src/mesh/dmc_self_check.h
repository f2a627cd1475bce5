#pragma once
// Private: Dual Marching Cubes checks its own output. Merged octree cells can make degenerate
// dual cells whose surface is not manifold, triangles that cross each other, or a surface that
// strays from the isosurface (a chord across an edge the QEF did not place a vertex on). The
// triangles concerned are found here and the merged cells behind them split back into voxels,
// until the mesh is clean or only voxel cells (plain Marching Cubes) remain.

#include <bitset>
#include <cstdint>
#include <vector>

#include "mesh/dmc_contour.h"
#include "mesh/dmc_grid.h"
#include "mesh/dmc_octree.h"

namespace vdbmesh::detail {

/// The voxels whose merged cells split_cells_of() split back into voxels, per leaf.
struct SplitVoxels {
    std::vector<std::bitset<512>> voxels;  ///< per leaf, by leaf_offset
    std::vector<std::uint8_t> changed;     ///< per leaf: any bit set
};

/// A voxel of a leaf: the leaf's index and the voxel's leaf_offset.
struct LeafVoxel {
    std::uint32_t leaf;
    std::uint16_t offset;
};

/// Triangles of @a contour made from merged cells that are in a self-intersecting pair, on a
/// non-manifold edge or vertex, on a vertex at the position of another, or whose centroid lies farther than @a tolerance
/// voxels from the isosurface (first-order distance |f - iso| / |grad f| of the trilinear field).
/// Sorted, unique. Only triangles that may change the answer are judged: without @a since,
/// those from merged cells (only they are refined); with @a since (the cells split since the
/// last check, whose result was acted on), those of dual cells with a corner in a split cell
/// (every other triangle is unchanged since). They are judged against the triangles sharing a
/// vertex with them or whose boxes come near theirs, so the answer equals the full check's.
std::vector<std::uint32_t> triangles_to_refine(const DmcGrid& grid, const DmcContour& contour, double tolerance,
                                               const SplitVoxels* since);

/// Splits into voxels the merged cells at the 8 corners of the dual cells that made
/// @a triangles, and records the voxels split in @a split (reset first). Returns whether
/// anything was split.
bool split_cells_of(const DmcGrid& grid, const DmcContour& contour, const std::vector<std::uint32_t>& triangles,
                    std::vector<LeafOctree>& octrees, SplitVoxels& split);

/// Splits the merged cells holding @a voxels, except those split since @a split was reset,
/// and records their voxels in @a split. Returns whether anything was split.
bool split_cells_at(const std::vector<LeafVoxel>& voxels, std::vector<LeafOctree>& octrees, SplitVoxels& split);

}  // namespace vdbmesh::detail
