#pragma once
// The sheets of the multi-label surface through one voxel corner (private to src/labels).
//
// Around a voxel corner lie 8 voxels (octant o = dx + 2 dy + 4 dz) and 12 faces between them
// (face f = 4 axis + bu + 2 bv: across `axis`, on the side bu of axis u = axis + 1 and bv of
// v = axis + 2, mod 3). A face between two different labels is a wall. On a small sphere round
// the corner each wall is an arc between two of the 6 edges from the corner; a label's
// boundary there is a set of closed curves of arcs. At an edge (4 voxels round it) a curve
// goes on along the next wall of its run of voxels, except where two diagonal voxels hold the
// same label and the other two differ from it: that label is either bridged through the edge
// (its curves cross over to the other voxel) or cut apart there. It is bridged when it wraps
// round the edge at both ends (the diagonal voxels joined through the layer beyond each end:
// cut apart, it would make a tunnel of zero width), or when the other two voxels differ from
// each other; between two diagonal labels (a checkerboard) neither wrapping round, the lower
// label is bridged, so the background flows between diagonal structures.
//
// The walls joined through the edges form classes; each class is one vertex (a sheet) of the
// mesh. A label stays manifold at the corner when each sheet holds at most one of its curves,
// and when its two pairs at an edge are not on one sheet at both ends of the edge.

#include <array>
#include <cstdint>
#include <functional>

namespace vdbmesh::labels_detail {

using CornerLabels = std::array<std::uint16_t, 8>;

constexpr int face_axis(int face) { return face >> 2; }
/// The octant on the low side of @a face.
constexpr int face_low_octant(int face) {
    const int axis = face >> 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
    return ((face & 1) << u) | (((face >> 1) & 1) << v);
}
constexpr int face_high_octant(int face) { return face_low_octant(face) | (1 << face_axis(face)); }

/// The 8 voxels round a corner and, per edge 2 axis + side (side 1: toward +axis), the 4
/// voxels beyond the far end of the edge (indexed like the block's octants of that layer: by
/// their two other bits, octant & ~(1 << axis) >> ... see far_index()).
struct CornerNeighbourhood {
    CornerLabels block;
    std::array<std::array<std::uint16_t, 4>, 6> far;
};
/// Index into CornerNeighbourhood::far[edge] of the voxel beyond the edge in line with octant @a o.
constexpr int far_index(int axis, int o) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    return ((o >> u) & 1) + 2 * ((o >> v) & 1);
}

struct CornerSheets {
    int count = 0;                      ///< sheets (vertices) at the corner
    std::array<std::int8_t, 12> sheet;  ///< per face: its sheet, -1 where it is no wall
};

CornerSheets corner_sheets(const CornerNeighbourhood& n);

/// 0 when every checked label is manifold at the corner, else one that is not.
/// @a checked(label): whether a label's manifoldness matters (the background's does not);
/// @a far_sheets(edge): the sheets at the far end of that edge (2 axis + side).
std::uint16_t corner_conflict(const CornerNeighbourhood& n, const CornerSheets& sheets,
                              const std::function<bool(std::uint16_t)>& checked,
                              const std::function<CornerSheets(int)>& far_sheets);

}  // namespace vdbmesh::labels_detail
