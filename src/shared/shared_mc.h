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

/// BlockMc::face_index of an edge that does not cross the surface.
inline constexpr std::uint16_t kMcNoEdge = 0xffff;

/// Marching Cubes of the cells whose minimum corner lies in one 8^3 block. Its vertices are the
/// crossings of the edges it owns (whose minimum corner lies in it) and the ones its triangles
/// borrow from the 7 blocks after it: a placed copy of the block writes its triangles as
/// @a corners plus the number of its first vertex, then overwrites the borrowed corners with
/// the neighbours' vertices (found through their face_index).
struct BlockMc {
    /// An owned crossing: its edge's first corner (from the block origin) and the crossing
    /// parameter on the edge's axis (0 on the others): placed at o, the vertex is
    /// (o + corner) + along per axis, as mesh_grid computes it.
    struct OwnedVertex {
        std::array<std::int32_t, 3> corner;
        std::array<double, 3> along;
    };
    /// The crossings of the owned edges, by edge code ((x * 8 + y) * 8 + z) * 3 + axis.
    std::vector<OwnedVertex> owned;
    /// The index in owned of each edge whose first corner lies on a first face of the block (the
    /// edges the blocks before it borrow), or kMcNoEdge: at face_slot(). Three faces of 1.1 KB
    /// rather than all 1,536 edges: the placed blocks read them for every borrowed vertex and
    /// the smaller table stays in cache.
    std::array<std::uint16_t, 3 * 8 * 8 * 3> face_index;
    /// Triangles: an own vertex as its index in owned; a borrowed one as 0 (see borrowed_corners).
    std::vector<std::array<std::uint32_t, 3>> corners;
    /// Borrowed vertices in order of first use: (d << 16) | face_slot() of the edge in block d
    /// (bits as in Key8).
    std::vector<std::uint32_t> borrowed;
    struct BorrowedCorner {
        std::uint32_t triangle;
        std::uint16_t corner;    ///< 0..2
        std::uint16_t borrowed;  ///< index in borrowed
    };
    std::vector<BorrowedCorner> borrowed_corners;  ///< in triangle order
    // The block's own mesh, for the instanced output and the area (block_marching_cubes()'s
    // with_part).
    double area = 0;                                       ///< in index units
    std::vector<std::array<float, 3>> part_vertices;       ///< every corner, index space from the block origin
    std::vector<std::array<std::uint32_t, 3>> part_triangles;
};

/// Where face_index holds the edge along @a axis from corner @a c, which lies on face @a face
/// (c[face] == 0): the face, then the two other coordinates in axis order, then the axis.
inline int face_slot(int face, const int c[3], int axis) {
    const int u = c[face == 0 ? 1 : 0], v = c[face == 2 ? 1 : 2];
    return ((face * 8 + u) * 8 + v) * 3 + axis;
}

/// The children a level-@a level neighbourhood @a parent covers: child (x, y, z) for 0 <= x, y,
/// z <= n (n children per axis; those with a coordinate n are first children of the nodes
/// after the parent), looked up once so that the neighbourhoods of all n^3 children are read
/// from them.
class ChildGrid {
public:
    ChildGrid(const SharedTree& tree, int level, const Key8& parent);
    /// The neighbourhood of child (x, y, z), 0 <= x, y, z < n.
    Key8 key(int x, int y, int z) const {
        const int i = (x * m_ + y) * m_ + z;
        return {refs_[i], refs_[i + m_ * m_], refs_[i + m_], refs_[i + m_ * m_ + m_],
                refs_[i + 1], refs_[i + m_ * m_ + 1], refs_[i + m_ + 1], refs_[i + m_ * m_ + m_ + 1]};
    }

    /// Whether the neighbourhood of child (x, y, z) lies inside the parent's own node and that
    /// node is a tile: then it is quiet (quiet_key()), without looking.
    bool inside_tile(int x, int y, int z) const { return tile_ && x < m_ - 2 && y < m_ - 2 && z < m_ - 2; }

private:
    int m_;  // n + 1
    bool tile_;  // the parent's own node (d = 0) is a tile
    std::vector<SharedRef> refs_;
};
/// Whether a neighbourhood is all tiles on one side of the surface (no surface in it).
bool quiet_key(const SharedTree& tree, const Key8& key);
/// The level-2 neighbourhoods that may hold surface: every root entry and the positions before it.
std::vector<std::pair<Coord3, Key8>> root_neighbourhoods(const SharedTree& tree);
/// Marching Cubes (inside: value < 0) of the block whose leaf-level neighbourhood is @a key;
/// its part and area only @a with_part (left empty and 0 otherwise).
BlockMc block_marching_cubes(const SharedTree& tree, const Key8& key, bool with_part);

}  // namespace vdbmesh::detail
