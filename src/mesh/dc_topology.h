#pragma once
// Private: the topology test of a merge whose children are all leaves merged before (or
// without surface), used within blocks from cells of 4 voxels up (dc_octree.cpp) and across
// blocks (dc_coarse_merge.cpp).
//
// Each such child holds one disk or nothing, each of its edges changes sign at most once and
// each of its faces carries at most one chain. So the surface of the union is known from the
// signs at the children's 27 corners alone:
//  - an edge of the cell changes sign at most once: its three samples change at most once;
//  - a face carries at most one chain: the chains of its four quarters (one on each quarter
//    whose corners differ), joined at the crossings of its four inner half edges, make one
//    path or nothing, and no loop;
//  - the inside is one disk: the children's disks, joined along the chains of the 12 inner
//    quarter faces and at the crossings of the 6 inner half edges, are connected, and by
//    inclusion-exclusion chi = disks - chains on inner faces + crossings on inner half edges
//    is 1.

#include <array>
#include <cstdint>

namespace vdbmesh::detail {

/// Whether each of the 27 corners of a candidate cell's children is inside: bit x * 9 + y * 3 + z
/// for the corner at (x, y, z) in 0..2 (in half cells from the cell's minimum corner).
using ChildCornerSigns = std::uint32_t;

/// The signs from @a inside(x, y, z), called for each corner.
template <typename Inside>
ChildCornerSigns child_corner_signs(Inside&& inside) {
    ChildCornerSigns signs = 0;
    for (int x = 0; x < 3; ++x) {
        for (int y = 0; y < 3; ++y) {
            for (int z = 0; z < 3; ++z) signs |= ChildCornerSigns(bool(inside(x, y, z))) << (x * 9 + y * 3 + z);
        }
    }
    return signs;
}

/// Whether the union of the children's surfaces is one disk meeting each edge of the cell at
/// most once and each face in at most one chain; @a surface[c] for child c = x + 2 y + 4 z.
bool union_is_one_disk(ChildCornerSigns signs, const std::array<bool, 8>& surface);

}  // namespace vdbmesh::detail
