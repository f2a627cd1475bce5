// A grid already in memory seen as regions (grid_region.h): read() copies the leaves and tiles
// that meet the box into a new tree with the grid's transform, background and metadata.

#include <openvdb/openvdb.h>

#include <algorithm>
#include <tuple>
#include <utility>
#include <vector>

#include "vdbmesh/error.h"
#include "vdbmesh/grid_region.h"

namespace vdbmesh {

namespace {

using Tree = openvdb::FloatTree;
using Upper = Tree::RootNodeType::ChildNodeType;
using Lower = Upper::ChildNodeType;
using Leaf = Lower::ChildNodeType;
static_assert(int(Lower::DIM) == kNodeVoxels, "a node is a lower internal node");

openvdb::CoordBBox to_bbox(const IndexBox& box) {
    return openvdb::CoordBBox(openvdb::Coord(box.min[0], box.min[1], box.min[2]), openvdb::Coord(box.max[0] - 1, box.max[1] - 1, box.max[2] - 1));
}

/// Whether node origin @a a comes before @a b in z-major order (z, then y, then x).
bool z_major_before(const std::array<std::int32_t, 3>& a, const std::array<std::int32_t, 3>& b) {
    return std::make_tuple(a[2], a[1], a[0]) < std::make_tuple(b[2], b[1], b[0]);
}

/// A tile of the root or an upper internal node: its box, value, state and level (for addTile).
struct Tile {
    openvdb::CoordBBox box;
    float value;
    bool active;
    openvdb::Index level;
};

class InMemoryRegions final : public GridRegionSource {
public:
    explicit InMemoryRegions(std::shared_ptr<const openvdb::FloatGrid> grid) : grid_(std::move(grid)) {
        grid_->tree().getNodes(lowers_);
        const float background = grid_->background();
        auto keep = [&](auto tile) { return tile.isValueOn() || *tile != background; };
        for (auto tile = grid_->tree().root().cbeginValueAll(); tile; ++tile) {
            if (keep(tile)) tiles_.push_back({openvdb::CoordBBox::createCube(tile.getCoord(), int(Upper::DIM)), *tile, tile.isValueOn(), 3});
        }
        std::vector<const Upper*> uppers;
        grid_->tree().getNodes(uppers);
        for (const Upper* upper : uppers) {
            for (auto tile = upper->cbeginValueAll(); tile; ++tile) {
                if (keep(tile)) tiles_.push_back({openvdb::CoordBBox::createCube(tile.getCoord(), int(Lower::DIM)), *tile, tile.isValueOn(), 2});
            }
        }
    }

    std::shared_ptr<const openvdb::FloatGrid> description() const override { return grid_->copyWithNewTree(); }

    std::vector<NodeWeight> nodes() const override {
        std::vector<NodeWeight> found;
        for (const Lower* lower : lowers_) {
            const std::uint64_t active = lower->onVoxelCount();
            const openvdb::Coord o = lower->origin();
            if (active > 0) found.push_back({{o.x(), o.y(), o.z()}, active});
        }
        // Active tiles above the nodes' level hold whole nodes.
        for (const Tile& tile : tiles_) {
            if (!tile.active) continue;
            const openvdb::Coord& lo = tile.box.min();
            const openvdb::Coord& hi = tile.box.max();
            for (int z = lo.z(); z <= hi.z(); z += kNodeVoxels) {
                for (int y = lo.y(); y <= hi.y(); y += kNodeVoxels) {
                    for (int x = lo.x(); x <= hi.x(); x += kNodeVoxels) {
                        found.push_back({{x, y, z}, std::uint64_t(kNodeVoxels) * kNodeVoxels * kNodeVoxels});
                    }
                }
            }
        }
        std::sort(found.begin(), found.end(), [](const NodeWeight& a, const NodeWeight& b) { return z_major_before(a.origin, b.origin); });
        return found;
    }

    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox& box) const override {
        const openvdb::CoordBBox wanted = to_bbox(box);
        openvdb::FloatGrid::Ptr region = grid_->copyWithNewTree();
        Tree& tree = region->tree();
        for (const Tile& tile : tiles_) {
            if (tile.box.hasOverlap(wanted)) tree.addTile(tile.level, tile.box.min(), tile.value, tile.active);
        }
        const float background = grid_->background();
        for (const Lower* lower : lowers_) {
            if (!lower->getNodeBoundingBox().hasOverlap(wanted)) continue;
            for (auto tile = lower->cbeginValueAll(); tile; ++tile) {
                if ((tile.isValueOn() || *tile != background) && openvdb::CoordBBox::createCube(tile.getCoord(), int(Leaf::DIM)).hasOverlap(wanted)) {
                    tree.addTile(1, tile.getCoord(), *tile, tile.isValueOn());
                }
            }
            for (auto leaf = lower->cbeginChildOn(); leaf; ++leaf) {
                if (leaf->getNodeBoundingBox().hasOverlap(wanted)) tree.addLeaf(new Leaf(*leaf));
            }
        }
        return region;
    }

    std::uint64_t estimated_bytes(const IndexBox& box) const override {
        const openvdb::CoordBBox wanted = to_bbox(box);
        std::uint64_t bytes = 0;
        for (const Lower* lower : lowers_) {
            if (lower->getNodeBoundingBox().hasOverlap(wanted)) bytes += lower->memUsage();
        }
        return bytes;
    }

private:
    std::shared_ptr<const openvdb::FloatGrid> grid_;
    std::vector<const Lower*> lowers_;
    std::vector<Tile> tiles_;
};

}  // namespace

std::unique_ptr<GridRegionSource> grid_regions_in_memory(std::shared_ptr<const openvdb::FloatGrid> grid) {
    if (!grid) throw Error("grid regions: no grid");
    return std::make_unique<InMemoryRegions>(std::move(grid));
}

}  // namespace vdbmesh
