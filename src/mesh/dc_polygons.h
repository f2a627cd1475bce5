#pragma once
// Private: the triangles of intersection-free octree contouring (dc_polygons.cpp), per block,
// with their vertices named by keys (a grid edge, a merged cell, a face between two merged
// cells) so that blocks weld them without coordinates.

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <vector>

#include "mesh/dc_block.h"

namespace vdbmesh::detail {

struct IfcVertex {
    std::uint64_t key;
    std::array<float, 3> position;  ///< world space
};

/// Whether @a key names a merged cell larger than a block: each block it covers lists its
/// vertex. Every other key is listed by one block only (a grid edge's crossing by the block
/// of its minimum sample, a cell of a block by that block), at most once.
bool ifc_key_of_coarse_cell(std::uint64_t key);

/// The grid point a key names (a grid edge's minimum sample, a cell's minimum corner): its
/// owner node is the node holding it (docs/dmc.md, "Bricks").
openvdb::Coord ifc_key_point(std::uint64_t key);

/// The key of the grid edge from @a min_sample along @a axis (0, 1, 2), as the blocks name
/// their crossings: Marching Cubes by bricks keys its vertices so too (marching_cubes.h).
/// @throw Error beyond the keys' coordinate range (+-2^18).
std::uint64_t ifc_edge_key(const openvdb::Coord& min_sample, int axis);

struct IfcBlockOutput {
    std::vector<IfcVertex> vertices;                     ///< unique keys but those of coarse cells
    std::vector<std::array<std::uint64_t, 3>> triangles;  ///< counter-clockwise seen from outside
};

/// Triangles of block @a block of @a grid (its samples as build_ifc_cells() kept them): Marching
/// Cubes in its unit cells, and the polygons of the crossed grid edges it owns that touch a
/// merged cell; such a polygon passes within @a error (voxels) of the edge's crossing, else the
/// fan round the crossing stands for it.
void contour_ifc_block(const SampleClassifier& classifier, openvdb::FloatGrid::ConstAccessor& accessor, const IfcCellGrid& grid,
                       std::size_t block, double error, const openvdb::math::Transform& transform, IfcBlockOutput& out);

}  // namespace vdbmesh::detail
