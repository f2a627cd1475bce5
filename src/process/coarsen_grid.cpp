// coarsen_grid(): a grid at twice the voxel size whose object holds the fine one's (coarsen_grid.h).
// Each coarse leaf is made on its own: the fine samples its voxels' neighbourhoods cover are
// copied into a dense block (from the fine leaves, or a tile's value where there is none), then
// pooled one axis at a time.
#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <vector>
#include <cstdlib>

#include "process/coarsen_grid.h"
#include "process/store_scan_box.h"
#include "vdbmesh/grid.h"

namespace vdbmesh::detail {
namespace {

using Leaf = openvdb::FloatTree::LeafNodeType;
constexpr int kLeafDim = int(Leaf::DIM);
/// Fine samples across a coarse leaf's neighbourhoods: 2 o - 1 .. 2 (o + kLeafDim - 1) + 1.
constexpr int kSpan = 2 * kLeafDim + 1;
constexpr float kNothing = -std::numeric_limits<float>::infinity();  ///< a sample off the scanned box

/// The fine samples round one coarse leaf, signed so that larger is more inside, and whether
/// each is active; index (x * kSpan + y) * kSpan + z from fine sample 2 origin - 1.
struct Block {
    std::array<float, kSpan * kSpan * kSpan> value;
    std::array<std::uint8_t, kSpan * kSpan * kSpan> active;
    static int at(int x, int y, int z) { return (x * kSpan + y) * kSpan + z; }
};

int floor_div(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
int floor_to(int a, int step) { return floor_div(a, step) * step; }
openvdb::Coord twice(const openvdb::Coord& c) { return {2 * c.x(), 2 * c.y(), 2 * c.z()}; }

class Coarsener {
public:
    Coarsener(const openvdb::FloatGrid& grid, Inside inside)
        : tree_(grid.tree()), sign_(inside == Inside::above ? 1.0f : -1.0f), box_(stored_scan_box(grid)) {}

    /// The coarse leaf at @a origin (coarse index space, a multiple of kLeafDim).
    std::unique_ptr<Leaf> leaf(const openvdb::Coord& origin) const {
        Block block;
        load(origin, block);
        static const bool centre_only = std::getenv("VDBMESH_CENTRE") != nullptr;  // EXPERIMENT
        if (!centre_only) pool(block);
        auto leaf = std::make_unique<Leaf>(origin, tree_.background(), false);
        openvdb::tree::ValueAccessor<const openvdb::FloatTree> accessor(tree_);
        for (int x = 0; x < kLeafDim; ++x) {
            for (int y = 0; y < kLeafDim; ++y) {
                for (int z = 0; z < kLeafDim; ++z) {
                    const int centre = Block::at(2 * x + 1, 2 * y + 1, 2 * z + 1);
                    const openvdb::Index offset = Leaf::coordToOffset(origin + openvdb::Coord(x, y, z));
                    const float value = block.value[std::size_t(centre)];
                    // (a neighbourhood all off the scanned box, which the meshers treat as
                    // outside: its own fine sample)
                    leaf->setValueOnly(offset, value != kNothing ? sign_ * value : accessor.getValue(twice(origin + openvdb::Coord(x, y, z))));
                    leaf->setActiveState(offset, block.active[std::size_t(centre)] != 0);
                }
            }
        }
        return leaf;
    }

private:
    /// The fine samples 2 origin - 1 + (0 .. kSpan - 1) per axis into @a block (off the scanned
    /// box: kNothing, inactive), from the fine leaves they lie in, or the value of the tile or
    /// background there.
    void load(const openvdb::Coord& origin, Block& block) const {
        const openvdb::Coord first = twice(origin) - openvdb::Coord(1);
        openvdb::tree::ValueAccessor<const openvdb::FloatTree> accessor(tree_);
        for (int lx = floor_to(first.x(), kLeafDim); lx < first.x() + kSpan; lx += kLeafDim) {
            for (int ly = floor_to(first.y(), kLeafDim); ly < first.y() + kSpan; ly += kLeafDim) {
                for (int lz = floor_to(first.z(), kLeafDim); lz < first.z() + kSpan; lz += kLeafDim) {
                    const openvdb::Coord leaf_origin(lx, ly, lz);
                    const Leaf* fine = accessor.probeConstLeaf(leaf_origin);
                    const float uniform = fine ? 0.0f : accessor.getValue(leaf_origin);
                    const bool uniform_on = fine ? false : accessor.isValueOn(leaf_origin);
                    const openvdb::Coord lo = openvdb::Coord::maxComponent(leaf_origin, first);
                    const openvdb::Coord hi = openvdb::Coord::minComponent(leaf_origin + openvdb::Coord(kLeafDim - 1),
                                                                           first + openvdb::Coord(kSpan - 1));
                    for (int x = lo.x(); x <= hi.x(); ++x) {
                        for (int y = lo.y(); y <= hi.y(); ++y) {
                            for (int z = lo.z(); z <= hi.z(); ++z) {
                                const openvdb::Coord ijk(x, y, z);
                                const auto i = std::size_t(Block::at(x - first.x(), y - first.y(), z - first.z()));
                                if (box_ && !box_->isInside(ijk)) {
                                    block.value[i] = kNothing, block.active[i] = 0;
                                } else if (fine) {
                                    const openvdb::Index offset = Leaf::coordToOffset(ijk);
                                    block.value[i] = sign_ * fine->getValue(offset), block.active[i] = fine->isValueOn(offset);
                                } else {
                                    block.value[i] = sign_ * uniform, block.active[i] = uniform_on;
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    /// Each sample at an odd index (a coarse sample's centre) becomes the largest of its 3 x 3 x 3
    /// neighbourhood, and active when one of them is: one axis at a time, over the centres' rows.
    static void pool(Block& block) {
        for (int axis = 0; axis < 3; ++axis) {
            const int stride = axis == 0 ? kSpan * kSpan : axis == 1 ? kSpan : 1;
            for (int a = 0; a < kSpan; ++a) {
                for (int b = 0; b < kSpan; ++b) {
                    for (int centre = 1; centre < kSpan; centre += 2) {
                        // (the other two axes' indices a, b, in the order of the layout)
                        const int base = axis == 0 ? Block::at(0, a, b) : axis == 1 ? Block::at(a, 0, b) : Block::at(a, b, 0);
                        const int i = base + centre * stride;
                        float& value = block.value[std::size_t(i)];
                        const float around = std::max(block.value[std::size_t(i - stride)], block.value[std::size_t(i + stride)]);
                        value = std::max(value, around);
                        block.active[std::size_t(i)] |= block.active[std::size_t(i - stride)] | block.active[std::size_t(i + stride)];
                    }
                }
            }
        }
    }

    const openvdb::FloatTree& tree_;
    float sign_;
    std::optional<openvdb::CoordBBox> box_;
};

/// The coarse leaves whose voxels' neighbourhoods meet a fine leaf.
std::vector<openvdb::Coord> coarse_leaf_origins(const openvdb::FloatTree& tree) {
    std::vector<openvdb::Coord> origins;
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
        const openvdb::Coord o = leaf->origin();
        // coarse samples c with 2c - 1 .. 2c + 1 meeting o .. o + kLeafDim - 1: o / 2 .. o / 2 + kLeafDim / 2
        const openvdb::Coord lo(floor_to(o.x() / 2, kLeafDim), floor_to(o.y() / 2, kLeafDim), floor_to(o.z() / 2, kLeafDim));
        const openvdb::Coord hi(floor_to(o.x() / 2 + kLeafDim / 2, kLeafDim), floor_to(o.y() / 2 + kLeafDim / 2, kLeafDim),
                                floor_to(o.z() / 2 + kLeafDim / 2, kLeafDim));
        for (int x = lo.x(); x <= hi.x(); x += kLeafDim) {
            for (int y = lo.y(); y <= hi.y(); y += kLeafDim) {
                for (int z = lo.z(); z <= hi.z(); z += kLeafDim) origins.emplace_back(x, y, z);
            }
        }
    }
    std::sort(origins.begin(), origins.end());
    origins.erase(std::unique(origins.begin(), origins.end()), origins.end());
    return origins;
}

}  // namespace

std::shared_ptr<openvdb::FloatGrid> coarsen_grid(const openvdb::FloatGrid& grid, Inside inside) {
    openvdb::FloatGrid::Ptr result = openvdb::gridPtrCast<openvdb::FloatGrid>(grid.copyGridWithNewTree());
    result->setTransform(grid.transform().copy());
    result->transform().preScale(2.0);
    // Tiles first (uniform regions, their coarse samples the same value), then the leaves over them.
    auto tile = grid.tree().cbeginValueAll();
    tile.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);  // tiles only
    for (; tile; ++tile) {
        if (!tile.isValueOn() && *tile == grid.tree().background()) continue;  // (as the new tree is already)
        const openvdb::CoordBBox fine = tile.getBoundingBox();
        const openvdb::CoordBBox coarse(openvdb::Coord(-floor_div(-fine.min().x(), 2), -floor_div(-fine.min().y(), 2), -floor_div(-fine.min().z(), 2)),
                                        openvdb::Coord(floor_div(fine.max().x(), 2), floor_div(fine.max().y(), 2), floor_div(fine.max().z(), 2)));
        if (!coarse.empty()) result->tree().fill(coarse, *tile, tile.isValueOn());
    }
    const std::vector<openvdb::Coord> origins = coarse_leaf_origins(grid.tree());
    std::vector<std::unique_ptr<Leaf>> leaves(origins.size());
    const Coarsener coarsener(grid, inside);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, origins.size(), 16), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) leaves[i] = coarsener.leaf(origins[i]);
    });
    for (std::unique_ptr<Leaf>& leaf : leaves) result->tree().addLeaf(leaf.release());
    if (const auto box = stored_scan_box(grid)) {
        // coarse samples whose neighbourhood 2c - 1 .. 2c + 1 meets the box
        const openvdb::Coord lo(-floor_div(-(box->min().x() - 1), 2), -floor_div(-(box->min().y() - 1), 2), -floor_div(-(box->min().z() - 1), 2));
        const openvdb::Coord hi(floor_div(box->max().x() + 1, 2), floor_div(box->max().y() + 1, 2), floor_div(box->max().z() + 1, 2));
        store_scan_box(*result, openvdb::CoordBBox(lo, hi));
    }
    return result;
}

}  // namespace vdbmesh::detail
