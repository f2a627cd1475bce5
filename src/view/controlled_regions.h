#pragma once
// A grid read by region whose reads heed the server's word to its background work (the scan's
// preparation, the splat tree's fit over a huge grid): each read waits while the work is
// paused (the page's camera moves) and gives up once it is stopped (the server closes).

#include <memory>
#include <string>
#include <utility>

#include "vdbmesh/background_control.h"
#include "vdbmesh/grid_region.h"

namespace vdbmesh::view {

/// @a source whose read() first passes @a control's checkpoint (Error(@a what + " was
/// stopped") once stopped).
class ControlledRegions final : public GridRegionSource {
public:
    ControlledRegions(std::shared_ptr<const GridRegionSource> source, const BackgroundControl& control, std::string what)
        : source_(std::move(source)), control_(control), what_(std::move(what)) {}
    std::shared_ptr<const openvdb::FloatGrid> description() const override { return source_->description(); }
    std::vector<NodeWeight> nodes() const override { return source_->nodes(); }
    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox& box) const override {
        control_.checkpoint(what_.c_str());
        return source_->read(box);
    }
    std::uint64_t estimated_bytes(const IndexBox& box) const override { return source_->estimated_bytes(box); }
    std::uint64_t grid_bytes(const IndexBox& box) const override { return source_->grid_bytes(box); }
    std::vector<LeafMask> active_leaves(const IndexBox& box) const override { return source_->active_leaves(box); }

private:
    std::shared_ptr<const GridRegionSource> source_;
    const BackgroundControl& control_;
    std::string what_;
};

}  // namespace vdbmesh::view
