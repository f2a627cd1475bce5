// The splat trees the page shows of a .vdb at its initial isovalue: the topology preview at
// once, the fitted tree when the background fit is done (view.h), and their framing box.

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <utility>

#include "vdbmesh/splats.h"
#include "vdbmesh/view.h"
#include "view/controlled_regions.h"

namespace vdbmesh {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

/// In parallel: a huge tree has millions of nodes.
void set_splat_box(ViewSplats& splats) {
    using Box = std::pair<std::array<double, 3>, std::array<double, 3>>;
    constexpr double kHuge = std::numeric_limits<double>::max();
    const Box empty{{kHuge, kHuge, kHuge}, {-kHuge, -kHuge, -kHuge}};
    const std::vector<SplatNode>& nodes = splats.tree->nodes;
    const auto join = [](Box a, const Box& b) {
        for (int i = 0; i < 3; ++i) {
            a.first[i] = std::min(a.first[i], b.first[i]);
            a.second[i] = std::max(a.second[i], b.second[i]);
        }
        return a;
    };
    const Box box = tbb::parallel_reduce(tbb::blocked_range<std::size_t>(0, nodes.size(), 4096), empty,
        [&](const auto& range, Box box) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                const SplatNode& node = nodes[i];
                if (node.child_count != 0) continue;
                for (int a = 0; a < 3; ++a) {
                    box.first[a] = std::min(box.first[a], double(node.centre[a]) - node.radius);
                    box.second[a] = std::max(box.second[a], double(node.centre[a]) + node.radius);
                }
            }
            return box;
        }, join);
    splats.box_min = box.first;
    splats.box_max = box.second;
}

std::shared_ptr<const ViewSplats> topology_preview_splats(const GridRegionSource& regions, double iso) {
    const auto start = std::chrono::steady_clock::now();
    SplatTree tree = build_topology_preview(regions);
    tree.iso = iso;  // what the page asks for; the preview itself holds no isovalue
    auto splats = std::make_shared<ViewSplats>();
    splats->tree = std::make_shared<const SplatTree>(std::move(tree));
    splats->preview = true;
    splats->seconds = seconds_since(start);
    set_splat_box(*splats);
    return splats;
}

std::shared_ptr<const ViewSplats> fit_view_splats(std::shared_ptr<const GridRegionSource> regions, double iso,
                                                  const BackgroundControl& control, std::uint64_t max_bytes) {
    const auto start = std::chrono::steady_clock::now();
    SplatOptions options;
    options.iso = iso;
    options.max_bytes = max_bytes;
    const view::ControlledRegions controlled(std::move(regions), control, "the splat tree's fit");
    auto splats = std::make_shared<ViewSplats>();
    splats->tree = std::make_shared<const SplatTree>(build_splat_tree(controlled, options));
    splats->seconds = seconds_since(start);
    set_splat_box(*splats);
    return splats;
}

}  // namespace vdbmesh
