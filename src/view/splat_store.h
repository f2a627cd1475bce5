#pragma once
// GET /api/splats: the splat hierarchy of the scan at an isovalue (built on the first request
// for it, the last few kept), and the nodes a camera sent by the page needs.

#include <cstddef>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include "vdbmesh/splats.h"
#include "vdbmesh/view.h"
#include "view/mesh_request.h"
#include "view/mesh_store.h"

namespace vdbmesh::view {

/// A tree made for the page and the seconds it took.
struct StoredSplats {
    std::shared_ptr<const SplatTree> tree;
    double seconds = 0;
    bool preview = false;  ///< the topology preview (ViewSplats::preview): no close-ups from it
};

/// What the page asks for: iso (the scan's initial one), vp (16 numbers, column-major, world
/// to clip), eye (3 numbers), focal (pixels per unit at w = 1), pixel (2), budget (200000),
/// closeup (the most triangles a close-up may have; none: splats only).
struct SplatRequest {
    double iso = 0;
    SplatView view;
    std::optional<std::size_t> close_up_triangles;
};

/// @throw UsageError naming the parameter for a missing or bad value.
SplatRequest parse_splat_request(const ParamLookup& param, double default_iso);

/// The selected nodes as the page draws them, back to back and little-endian: per node
/// centre (float32 x 3), normal (float32 x 3), radius (float32): 28 bytes a node.
std::string splat_buffers(const SplatTree& tree, const SplatSelection& selection);
/// The same of nodes already placed (a shared tree's selection).
std::string splat_buffers(const std::vector<SplatNode>& nodes);

class SplatStore {
public:
    /// @a initial (when set): the tree at @a initial_iso made before serving, kept for good.
    /// Trees at other isovalues within @a other_max_bytes (ViewServerOptions::other_splat_tree_bytes).
    SplatStore(std::shared_ptr<const ViewScan> scan, std::shared_ptr<const ViewSplats> initial, double initial_iso,
               std::uint64_t other_max_bytes = 0);
    /// The tree of the scan's full grid at @a iso (read by region when not held), built now unless kept.
    /// @throw UsageError when the source is a mesh file (no grid to fit), ScanPreparing before
    /// set_scan() when the tree is not the initial one.
    std::shared_ptr<const StoredSplats> tree(double iso);
    /// The scan prepared in the background (ViewSource::prepare_scan).
    void set_scan(std::shared_ptr<const ViewScan> scan) { std::atomic_store(&scan_, std::move(scan)); }
    /// The tree at the initial isovalue fitted in the background (ViewSource::fit_splats), in
    /// place of the topology preview.
    void set_initial(std::shared_ptr<const ViewSplats> fitted);
    /// The tree at the initial isovalue as it stands (null: none made before serving).
    std::shared_ptr<const ViewSplats> initial() const;

private:
    static constexpr std::size_t kKept = 2;
    std::shared_ptr<const ViewScan> scan_;
    mutable std::mutex initial_mutex_;
    std::shared_ptr<const ViewSplats> initial_splats_;
    std::shared_ptr<const StoredSplats> initial_;
    double initial_iso_ = 0;
    std::uint64_t other_max_bytes_ = 0;
    std::mutex mutex_;
    std::deque<std::pair<double, std::shared_ptr<const StoredSplats>>> kept_;  ///< newest first
};

}  // namespace vdbmesh::view
