// Which blocks of cells can hold part of the surface. Sample values differ from one another
// only inside leaf nodes; tiles and the background are constant. So a cell with a sign change
// has a sample in a leaf, or straddles the boundary of a tile whose classification differs
// from its neighbour's (some tile classified unlike the background), or straddles the scan
// box with an inside sample. The cell with minimum corner p uses samples p..p+1, so the cells
// touching a region [a, b] of samples have minimum corners in [a - 1, b].

#include "mesh/surface_blocks.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cstdint>

namespace vdbmesh::detail {

namespace {

openvdb::Coord block_origin(const openvdb::Coord& ijk) {
    return openvdb::Coord(ijk.x() & ~(kBlockDim - 1), ijk.y() & ~(kBlockDim - 1), ijk.z() & ~(kBlockDim - 1));
}

/// Appends the blocks of the cells that straddle the boundary of the sample box @a box:
/// minimum corners in [min - 1, max] but not in [min, max - 1]; those with origins in
/// @a within only.
template <typename Keep>
void append_shell_blocks(const openvdb::CoordBBox& box, const openvdb::CoordBBox& within, Keep keep, std::vector<openvdb::Coord>& blocks) {
    const openvdb::Coord lo = openvdb::Coord::maxComponent(block_origin(box.min().offsetBy(-1)), block_origin(within.min()));
    const openvdb::Coord hi = openvdb::Coord::minComponent(block_origin(box.max()), block_origin(within.max()));
    const openvdb::CoordBBox interior(box.min(), box.max().offsetBy(-1));
    for (int x = lo.x(); x <= hi.x(); x += kBlockDim) {
        for (int y = lo.y(); y <= hi.y(); y += kBlockDim) {
            for (int z = lo.z(); z <= hi.z(); z += kBlockDim) {
                const openvdb::Coord origin(x, y, z);
                const openvdb::CoordBBox block(origin, origin.offsetBy(kBlockDim - 1));
                if (!interior.isInside(block) && within.isInside(origin) && keep(origin)) blocks.push_back(origin);
            }
        }
    }
}

/// Calls @a visit(box) for each tile of the tree's root and internal nodes whose value
/// @a keep accepts. Node by node over each one's table: the tree's own value iterator,
/// limited to the tiles' depth, cost about 12 M instructions on the walnut in this serial step.
template <typename Keep, typename Visit>
void for_each_tile(const openvdb::FloatTree& tree, Keep&& keep, Visit&& visit) {
    using Upper = openvdb::FloatTree::RootNodeType::ChildNodeType;
    using Lower = Upper::ChildNodeType;
    const auto visit_tiles = [&](auto tile, int tile_dim) {
        for (; tile; ++tile) {
            if (keep(*tile)) visit(openvdb::CoordBBox::createCube(tile.getCoord(), tile_dim));
        }
    };
    visit_tiles(tree.root().cbeginValueAll(), int(Upper::DIM));
    std::vector<const Upper*> uppers;
    tree.getNodes(uppers);
    for (const Upper* node : uppers) visit_tiles(node->cbeginValueAll(), int(Lower::DIM));
    std::vector<const Lower*> lowers;
    tree.getNodes(lowers);
    for (const Lower* node : lowers) visit_tiles(node->cbeginValueAll(), int(Lower::ChildNodeType::DIM));
}

}  // namespace

std::vector<openvdb::Coord> surface_blocks(const openvdb::FloatGrid& grid, const SampleClassifier& classifier,
                                           const std::optional<openvdb::CoordBBox>& within) {
    const openvdb::FloatTree& tree = grid.tree();
    std::vector<openvdb::Coord> blocks;
    const openvdb::CoordBBox region = within ? *within : openvdb::CoordBBox::inf();
    auto kept = [&](const openvdb::Coord& origin) { return region.isInside(origin); };
    // A leaf at L lists the blocks L - (0 or 8 on each axis): those within the box come from
    // leaves in [min, max + 8].
    using Lower = openvdb::FloatTree::RootNodeType::ChildNodeType::ChildNodeType;
    std::vector<const Lower*> lowers;
    tree.getNodes(lowers);
    const openvdb::CoordBBox leaves_wanted = within ? openvdb::CoordBBox(within->min(), within->max().offsetBy(kBlockDim)) : region;
    for (const Lower* node : lowers) {
        if (!leaves_wanted.hasOverlap(node->getNodeBoundingBox())) continue;
        for (auto leaf = node->cbeginChildOn(); leaf; ++leaf) {
            const openvdb::Coord origin = leaf->origin();
            for (int d = 0; d < 8; ++d) {
                const openvdb::Coord block = origin.offsetBy(-kBlockDim * (d & 1), -kBlockDim * ((d >> 1) & 1), -kBlockDim * (d >> 2));
                if (kept(block)) blocks.push_back(block);
            }
        }
    }
    const bool background_inside = classifier.inside(grid.background());
    for_each_tile(
        tree, [&](float value) { return classifier.inside(value) != background_inside; },
        [&](const openvdb::CoordBBox& box) { append_shell_blocks(box, region, [](const openvdb::Coord&) { return true; }, blocks); });
    if (const auto& box = classifier.scan_box()) {
        // A block straddling the box needs a visit when a tile or the background next to it is
        // inside (leaves are already listed).
        auto accessor = grid.getConstAccessor();
        auto meets_inside = [&](const openvdb::Coord& origin) {
            for (int d = 0; d < 8; ++d) {
                const openvdb::Coord sample = origin.offsetBy(kBlockDim * (d & 1), kBlockDim * ((d >> 1) & 1), kBlockDim * (d >> 2));
                if (!accessor.probeConstLeaf(sample) && classifier.inside(accessor.getValue(sample))) return true;
            }
            return false;
        };
        append_shell_blocks(*box, region, meets_inside, blocks);
    }
    tbb::parallel_sort(blocks.begin(), blocks.end());  // eight per leaf: the longest serial step here
    blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
    return blocks;
}

bool block_may_hold_surface(openvdb::FloatGrid::ConstAccessor& accessor, const SampleClassifier& classifier,
                            const openvdb::Coord& origin) {
    // The block's cells read samples origin .. origin + 8: its own leaf's region and the first
    // plane, line or sample of the 7 regions above it.
    const openvdb::CoordBBox window(origin, origin.offsetBy(kBlockDim));
    if (classifier.scan_box() && !classifier.scan_box()->isInside(window)) return true;
    using Leaf = openvdb::FloatTree::LeafNodeType;
    bool seen[2] = {false, false};
    for (int region = 0; region < 8; ++region) {
        const int d[3] = {region >> 2, (region >> 1) & 1, region & 1};
        const openvdb::Coord corner = origin.offsetBy(d[0] * kBlockDim, d[1] * kBlockDim, d[2] * kBlockDim);
        const Leaf* leaf = accessor.probeConstLeaf(corner);
        if (!leaf) {
            seen[classifier.inside(accessor.getValue(corner))] = true;
        } else {
            // Along an axis the region is the whole leaf (d = 0) or its first plane (d = 1).
            const int extent[3] = {d[0] ? 1 : kBlockDim, d[1] ? 1 : kBlockDim, d[2] ? 1 : kBlockDim};
            const float* values = leaf->buffer().data();
            const std::uint32_t all = (1u << extent[2]) - 1;
            for (int x = 0; x < extent[0]; ++x) {
                for (int y = 0; y < extent[1]; ++y) {
                    const std::uint32_t inside = classifier.inside_bits(values + Leaf::coordToOffset(openvdb::Coord(x, y, 0)), extent[2]);
                    seen[1] |= inside != 0;
                    seen[0] |= inside != all;
                    if (seen[0] && seen[1]) return true;
                }
            }
        }
        if (seen[0] && seen[1]) return true;
    }
    return false;
}

}  // namespace vdbmesh::detail
