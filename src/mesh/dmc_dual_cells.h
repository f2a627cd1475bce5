#pragma once
// Private: the dual cells of the leaf octrees (Schaefer and Warren 2004), enumerated without
// recursion. Every voxel corner p + 1/2 is owned by the leaf holding voxel p; a dual cell sits
// there iff p + 1/2 is a corner of at least one octree cell among the 8 voxels p + {0,1}^3,
// and its 8 corners are the vertices of the cells holding those voxels (repeated where cell
// sizes change: degenerate dual cells).

#include <array>
#include <vector>

#include "mesh/dmc_grid.h"
#include "mesh/dmc_octree.h"

namespace vdbmesh::detail {

/// A corner of a dual cell: the octree cell holding one voxel, and its vertex.
struct DualCorner {
    openvdb::Coord min;  ///< the cell's minimum voxel
    int size = 1;        ///< its edge in voxels (1, 2, 4 or 8)
    Point3d position;    ///< its vertex (index space)
    double value = 0.0;  ///< the value at the vertex
};

struct DualCell {
    openvdb::Coord p;  ///< the dual cell sits at voxel corner p + 1/2
    unsigned config;   ///< bit c set when corner c is inside
    std::array<DualCorner, 8> corners;  ///< corner c holds voxel p + (c & 1, c >> 1 & 1, c >> 2 & 1)
};

/// Voxel (x, y, z) of @a block (local coordinates in [-1, 8]) as a unit cell: its sample.
DualCorner sample_corner(const SampleBlock& block, int x, int y, int z);

/// The cell holding voxel @a local (relative to leaf @a leaf's origin, coordinates in [-1, 8]),
/// with @a block the leaf's sample block.
DualCorner dual_corner(const DmcGrid& grid, const std::vector<LeafOctree>& octrees, std::size_t leaf,
                       const SampleBlock& block, int x, int y, int z);

/// Appends to @a cells the dual cells owned by leaf @a leaf whose corners are not all on one
/// side (with open_boundary, only those inside the scan box).
void collect_dual_cells(const DmcGrid& grid, const std::vector<LeafOctree>& octrees, std::size_t leaf,
                        const SampleBlock& block, std::vector<DualCell>& cells);

}  // namespace vdbmesh::detail
