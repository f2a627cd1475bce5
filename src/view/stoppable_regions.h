#pragma once
// A grid read by region whose reads give up once a flag is set: the server's background work
// over a huge grid (the scan's preparation, the splat tree's fit) stops when the server closes.

#include <atomic>
#include <memory>
#include <string>
#include <utility>

#include "vdbmesh/error.h"
#include "vdbmesh/grid_region.h"

namespace vdbmesh::view {

/// @a source whose read() throws Error(@a what + " was stopped") once @a stop is set.
class StoppableRegions final : public GridRegionSource {
public:
    StoppableRegions(std::shared_ptr<const GridRegionSource> source, const std::atomic<bool>& stop, std::string what)
        : source_(std::move(source)), stop_(stop), what_(std::move(what)) {}
    std::shared_ptr<const openvdb::FloatGrid> description() const override { return source_->description(); }
    std::vector<NodeWeight> nodes() const override { return source_->nodes(); }
    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox& box) const override {
        if (stop_) throw Error(what_ + " was stopped");
        return source_->read(box);
    }
    std::uint64_t estimated_bytes(const IndexBox& box) const override { return source_->estimated_bytes(box); }
    std::uint64_t grid_bytes(const IndexBox& box) const override { return source_->grid_bytes(box); }
    std::vector<LeafMask> active_leaves(const IndexBox& box) const override { return source_->active_leaves(box); }

private:
    std::shared_ptr<const GridRegionSource> source_;
    const std::atomic<bool>& stop_;
    std::string what_;
};

}  // namespace vdbmesh::view
