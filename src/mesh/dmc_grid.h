#pragma once
// Private: the grid as Dual Marching Cubes reads it. Leaves in tree order, each leaf's 26
// neighbour leaves, and per leaf a dense block of its samples with a one-voxel ring taken
// from the neighbours (tiles and the background stand in as virtual voxels with their value;
// samples outside the scanned box hold outside_scan_value()).

#include <openvdb/openvdb.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "vdbmesh/mesher.h"

namespace vdbmesh::detail {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;
inline constexpr int kLeafDim = int(FloatLeaf::DIM);  // 8

/// Slot of the neighbour block at offset (dx, dy, dz) in {-1, 0, 1}^3; 13 is the leaf itself.
inline int neighbour_slot(int dx, int dy, int dz) { return (dx + 1) + 3 * (dy + 1) + 9 * (dz + 1); }
/// Block offset (-1, 0 or 1) of a local coordinate in [-8, 15].
inline int block_offset(int local) { return local < 0 ? -1 : (local >= kLeafDim ? 1 : 0); }

struct DmcGrid {
    const openvdb::FloatGrid* grid = nullptr;
    double iso = 0.0;
    bool inside_above = true;
    bool open_boundary = false;
    std::optional<openvdb::CoordBBox> scan_box;
    std::vector<const FloatLeaf*> leaves;                 ///< tree order (deterministic)
    std::vector<std::array<std::int32_t, 27>> neighbours;  ///< leaf index per neighbour_slot, -1: none
    /// Per leaf and neighbour_slot without a leaf there: the value of the tile or background
    /// that holds that block (read once here, not through the tree for every sample block).
    std::vector<std::array<float, 27>> tile_values;

    bool inside(double value) const { return inside_above ? value > iso : value < iso; }
    /// Whether @a holds(n) for the index n of a leaf among leaf @a leaf's 27 neighbours (itself
    /// included).
    template <typename Holds>
    bool any_neighbour(std::size_t leaf, Holds&& holds) const {
        return std::any_of(neighbours[leaf].begin(), neighbours[leaf].end(),
                           [&](std::int32_t n) { return n >= 0 && holds(std::size_t(n)); });
    }
    bool in_box(const openvdb::Coord& ijk) const { return !scan_box || scan_box->isInside(ijk); }
    /// Index of the leaf holding voxel @a local (relative to leaf @a leaf's origin, each
    /// coordinate in [-8, 15]), or -1 when a tile or the background holds it.
    std::int32_t leaf_at(std::size_t leaf, int x, int y, int z) const {
        return neighbours[leaf][neighbour_slot(block_offset(x), block_offset(y), block_offset(z))];
    }
};

DmcGrid make_dmc_grid(const openvdb::FloatGrid& grid, const MeshOptions& options);

/// Values of voxels origin + [-1, 8]^3 of one leaf, z fastest (as in a leaf node).
struct SampleBlock {
    static constexpr int kDim = kLeafDim + 2;
    static int index(int x, int y, int z) { return ((x + 1) * kDim + (y + 1)) * kDim + (z + 1); }
    openvdb::Coord origin;
    std::array<double, kDim * kDim * kDim> value;
    std::array<bool, kDim * kDim * kDim> inside;
    double at(int x, int y, int z) const { return value[index(x, y, z)]; }
};

/// Fills @a block for leaf @a leaf.
void load_sample_block(const DmcGrid& grid, std::size_t leaf, SampleBlock& block);

/// The value of one voxel of a SampleBlock of leaf @a leaf (local coordinates in [-1, 8]),
/// read without loading the block.
double sample_value(const DmcGrid& grid, std::size_t leaf, int x, int y, int z);

}  // namespace vdbmesh::detail
