// Which blocks of cells can hold part of the surface. Sample values differ from one another
// only inside leaf nodes; tiles and the background are constant. So a cell with a sign change
// has a sample in a leaf, or straddles the boundary of a tile whose classification differs
// from its neighbour's (some tile classified unlike the background), or straddles the scan
// box with an inside sample. The cell with minimum corner p uses samples p..p+1, so the cells
// touching a region [a, b] of samples have minimum corners in [a - 1, b].

#include "mesh/surface_blocks.h"

#include <algorithm>

namespace vdbmesh::detail {

namespace {

openvdb::Coord block_origin(const openvdb::Coord& ijk) {
    return openvdb::Coord(ijk.x() & ~(kBlockDim - 1), ijk.y() & ~(kBlockDim - 1), ijk.z() & ~(kBlockDim - 1));
}

/// Appends the blocks of the cells that straddle the boundary of the sample box @a box:
/// minimum corners in [min - 1, max] but not in [min, max - 1].
template <typename Keep>
void append_shell_blocks(const openvdb::CoordBBox& box, Keep keep, std::vector<openvdb::Coord>& blocks) {
    const openvdb::Coord lo = block_origin(box.min().offsetBy(-1));
    const openvdb::Coord hi = block_origin(box.max());
    const openvdb::CoordBBox interior(box.min(), box.max().offsetBy(-1));
    for (int x = lo.x(); x <= hi.x(); x += kBlockDim) {
        for (int y = lo.y(); y <= hi.y(); y += kBlockDim) {
            for (int z = lo.z(); z <= hi.z(); z += kBlockDim) {
                const openvdb::Coord origin(x, y, z);
                const openvdb::CoordBBox block(origin, origin.offsetBy(kBlockDim - 1));
                if (!interior.isInside(block) && keep(origin)) blocks.push_back(origin);
            }
        }
    }
}

}  // namespace

std::vector<openvdb::Coord> surface_blocks(const openvdb::FloatGrid& grid, const SampleClassifier& classifier) {
    const openvdb::FloatTree& tree = grid.tree();
    std::vector<openvdb::Coord> blocks;
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
        const openvdb::Coord origin = leaf->origin();
        for (int d = 0; d < 8; ++d) {
            blocks.push_back(origin.offsetBy(-kBlockDim * (d & 1), -kBlockDim * ((d >> 1) & 1), -kBlockDim * (d >> 2)));
        }
    }
    const bool background_inside = classifier.inside(grid.background());
    auto always = [](const openvdb::Coord&) { return true; };
    auto tile = tree.cbeginValueAll();
    tile.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);
    for (; tile; ++tile) {
        if (classifier.inside(*tile) != background_inside) append_shell_blocks(tile.getBoundingBox(), always, blocks);
    }
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
        append_shell_blocks(*box, meets_inside, blocks);
    }
    std::sort(blocks.begin(), blocks.end());
    blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
    return blocks;
}

}  // namespace vdbmesh::detail
