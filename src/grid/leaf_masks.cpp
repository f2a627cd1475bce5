// The active leaves of a region (grid_region.h): each leaf's value mask, clipped to the box.

#include "leaf_masks.h"

#include <algorithm>
#include <cstdint>
#include <tuple>

#include "region_walk.h"

namespace vdbmesh::detail {
namespace {

using region_walk::Leaf;
static_assert(Leaf::DIM == 8 && Leaf::NodeMaskType::WORD_COUNT == 8, "a LeafMask is an 8^3 leaf's mask, a 64-bit word per x");

/// The bits of one x row (bit y * 8 + z) with y in [y0, y1) and z in [z0, z1).
std::uint64_t row_bits(int y0, int y1, int z0, int z1) {
    std::uint64_t bits = 0;
    for (int y = y0; y < y1; ++y)
        for (int z = z0; z < z1; ++z) bits |= std::uint64_t{1} << (y * 8 + z);
    return bits;
}

/// @a leaf's mask cleared outside @a box (inclusive): whole words when it lies inside.
LeafMask clipped_mask(const Leaf& leaf, const openvdb::CoordBBox& box) {
    LeafMask mask;
    const openvdb::Coord origin = leaf.origin();
    mask.origin = {origin.x(), origin.y(), origin.z()};
    const auto& words = leaf.getValueMask();
    std::array<int, 3> lo{}, hi{};  // the box in the leaf's offsets, [lo, hi); 64 bits: the box may span every int
    for (int a = 0; a < 3; ++a) {
        lo[a] = int(std::clamp<std::int64_t>(std::int64_t{box.min()[a]} - origin[a], 0, 8));
        hi[a] = int(std::clamp<std::int64_t>(std::int64_t{box.max()[a]} + 1 - origin[a], 0, 8));
    }
    const std::uint64_t rows = row_bits(lo[1], hi[1], lo[2], hi[2]);
    for (int x = lo[0]; x < hi[0]; ++x) mask.on[x] = words.getWord<std::uint64_t>(x) & rows;
    return mask;
}

bool empty(const LeafMask& mask) {
    return std::all_of(mask.on.begin(), mask.on.end(), [](std::uint64_t word) { return word == 0; });
}

}  // namespace

std::vector<LeafMask> leaf_masks(const openvdb::FloatTree& tree, const IndexBox& box) {
    region_walk::TreeRegion region{region_walk::to_bbox(box), nullptr, {}};
    region_walk::walk_region(tree, region);
    std::vector<LeafMask> masks;
    masks.reserve(region.leaves.size());
    for (const Leaf* leaf : region.leaves) {
        LeafMask mask = clipped_mask(*leaf, region.box);
        if (!empty(mask)) masks.push_back(mask);
    }
    std::sort(masks.begin(), masks.end(), [](const LeafMask& a, const LeafMask& b) {
        return std::tie(a.origin[2], a.origin[1], a.origin[0]) < std::tie(b.origin[2], b.origin[1], b.origin[0]);
    });
    return masks;
}

}  // namespace vdbmesh::detail

namespace vdbmesh {

std::vector<LeafMask> GridRegionSource::active_leaves(const IndexBox& box) const {
    return detail::leaf_masks(read(box)->tree(), box);
}

}  // namespace vdbmesh
