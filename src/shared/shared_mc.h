#pragma once
// Private: neighbourhoods of the shared tree (a node and the 7 after it) and Marching Cubes of
// one 8^3 block of cells from its neighbourhood, translation-free so that it can be reused.

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "vdbmesh/shared_tree.h"

namespace vdbmesh::detail {

/// The refs of a node (d = 0) and its neighbours d = 1..7 (bit a of d: the next node along axis a).
using Key8 = std::array<SharedRef, 8>;

/// As edge_crossing.h of the mesh stage: crossings kept this far from the samples.
inline constexpr double kMcCrossingMargin = 1e-3;
/// A triangle corner on an edge the block owns: this bit | the edge's index in BlockMc::edges.
/// Otherwise (d << 16) | edge code, d the neighbour block (bits as in Key8).
inline constexpr std::uint32_t kMcOwnVertex = 1u << 31;

/// Marching Cubes of the cells whose minimum corner lies in one 8^3 block.
struct BlockMc {
    std::vector<std::uint16_t> edges;  ///< owned crossing edges ((x * 8 + y) * 8 + z) * 3 + axis, sorted
    std::vector<double> t;             ///< their crossing parameters
    std::vector<std::uint16_t> index_of;  ///< per edge code (8 * 8 * 8 * 3): its index in edges, when it crosses
    std::vector<std::array<std::uint32_t, 3>> triangles;  ///< corners as kMcOwnVertex / neighbour refs
    double area = 0;                                       ///< in index units
    std::vector<std::array<float, 3>> part_vertices;       ///< every corner, index space from the block origin
    std::vector<std::array<std::uint32_t, 3>> part_triangles;
};

/// The neighbourhood of child (cx, cy, cz) of the level-@a level neighbourhood @a parent.
Key8 child_key(const SharedTree& tree, int level, const Key8& parent, int cx, int cy, int cz);
/// Whether a neighbourhood is all tiles on one side of the surface (no surface in it).
bool quiet_key(const SharedTree& tree, const Key8& key);
/// The level-2 neighbourhoods that may hold surface: every root entry and the positions before it.
std::vector<std::pair<Coord3, Key8>> root_neighbourhoods(const SharedTree& tree);
/// Marching Cubes (inside: value < 0) of the block whose leaf-level neighbourhood is @a key.
BlockMc block_marching_cubes(const SharedTree& tree, const Key8& key);

}  // namespace vdbmesh::detail
