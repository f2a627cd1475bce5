#pragma once
// Private: the depth-3 octree of each 8^3 leaf (Schaefer and Warren 2004, section 3). Its unit
// cell is the voxel: a unit cube centred on the sample, whose vertex is the sample itself.
// Cells of 2, 4 and 8 voxels exist where 8 children were merged because no surface passes
// there, or their 4D QEF error stayed under the tolerance and the merge keeps the surface's
// topology (dmc_octree.cpp).

#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "mesh/dmc_grid.h"
#include "mesh/edge_crossing.h"

namespace vdbmesh::detail {

/// Offset of local voxel (x, y, z) in [0, 8)^3 within a leaf, as in a leaf node (z fastest).
inline int leaf_offset(int x, int y, int z) { return (x << 6) | (y << 3) | z; }

/// The vertex of a merged cell: the QEF minimiser (index space) and the value there (in the
/// grid's units).
struct CellVertex {
    Point3d position;
    double value;
};

struct LeafOctree {
    std::vector<std::uint8_t> level;          ///< per voxel offset: level of its cell; empty: all 0
    std::vector<std::uint16_t> merged_min;    ///< sorted offsets of the merged cells' minimum voxels
    std::vector<CellVertex> merged_vertex;    ///< their vertices, in the same order
    /// Every cell the bottom-up merge made, at any level (level << 9 | minimum voxel offset,
    /// sorted), with its vertex: splitting a cell brings back its largest merged descendants.
    std::vector<std::uint16_t> built_key;
    std::vector<CellVertex> built_vertex;

    int level_at(int offset) const { return level.empty() ? 0 : level[offset]; }
    const CellVertex& vertex_at(int min_offset) const {
        const auto it = std::lower_bound(merged_min.begin(), merged_min.end(), std::uint16_t(min_offset));
        return merged_vertex[std::size_t(it - merged_min.begin())];
    }
    bool has_merges() const { return !merged_min.empty(); }
    /// Splits the merged cell holding voxel @a offset into its largest merged descendants
    /// (voxels where none was merged).
    void split_cell(int offset);
    /// Makes cells of the largest built cells below level @a below in the cube of @a extent
    /// voxels at local voxel (x, y, z), whose voxels are all unit cells.
    void expand(int x, int y, int z, int extent, int below);
};

/// Whether a leaf among leaf @a leaf's 27 neighbours (itself included) has merged cells.
inline bool neighbourhood_has_merges(const DmcGrid& grid, const std::vector<LeafOctree>& octrees, std::size_t leaf) {
    return grid.any_neighbour(leaf, [&](std::size_t n) { return octrees[n].has_merges(); });
}

/// Builds the octree of every leaf. error <= 0: no merging (every voxel is a cell).
/// @a progress (may be empty) gets the fraction of leaves done.
std::vector<LeafOctree> build_leaf_octrees(const DmcGrid& grid, double error);

}  // namespace vdbmesh::detail
