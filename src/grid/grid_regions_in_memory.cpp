// A grid already in memory seen as regions (grid_region.h): read() copies the leaves and tiles
// that meet the box (region_walk.h's walk, as the .vdb and scan sources do) into a new tree with
// the grid's transform, background and metadata.

#include <openvdb/openvdb.h>

#include <utility>
#include <vector>

#include "region_walk.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid_region.h"

namespace vdbmesh {

namespace {

using detail::region_walk::Leaf;
using detail::region_walk::Lower;
using detail::region_walk::to_bbox;
using detail::region_walk::TreeRegion;

class InMemoryRegions final : public GridRegionSource {
public:
    explicit InMemoryRegions(std::shared_ptr<const openvdb::FloatGrid> grid) : grid_(std::move(grid)) {
        grid_->tree().getNodes(lowers_);
    }

    std::shared_ptr<const openvdb::FloatGrid> description() const override { return grid_->copyWithNewTree(); }

    std::vector<NodeWeight> nodes() const override { return detail::region_walk::node_weights(grid_->tree()); }

    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox& box) const override {
        openvdb::FloatGrid::Ptr region = grid_->copyWithNewTree();
        TreeRegion met{to_bbox(box), &region->tree(), {}};
        detail::region_walk::walk_region(grid_->tree(), met);
        for (const Leaf* leaf : met.leaves) region->tree().addLeaf(new Leaf(*leaf));
        return region;
    }

    /// What the nodes meeting the box hold in memory.
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
};

}  // namespace

std::unique_ptr<GridRegionSource> grid_regions_in_memory(std::shared_ptr<const openvdb::FloatGrid> grid) {
    if (!grid) throw Error("grid regions: no grid");
    return std::make_unique<InMemoryRegions>(std::move(grid));
}

}  // namespace vdbmesh
