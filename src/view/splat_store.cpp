#include "view/splat_store.h"

#include <chrono>
#include <cstring>
#include <sstream>

#include "vdbmesh/error.h"

namespace vdbmesh::view {
namespace {

double positive(const ParamLookup& param, const std::string& parameter, double fallback) {
    const auto text = param(parameter);
    if (!text) return fallback;
    const double value = number_param(parameter, *text);
    if (!(value > 0)) throw UsageError(parameter + ": expected a number > 0, got \"" + *text + "\"");
    return value;
}

void put_floats(std::string& out, std::initializer_list<float> values) {
    for (float v : values) {
        char bytes[4];
        std::memcpy(bytes, &v, 4);
        out.append(bytes, 4);
    }
}

}  // namespace

SplatRequest parse_splat_request(const ParamLookup& param, double default_iso) {
    SplatRequest request;
    request.iso = default_iso;
    if (auto iso = param("iso")) request.iso = number_param("iso", *iso);
    request.view.view_projection = number_params<16>(param, "vp");
    request.view.eye = number_params<3>(param, "eye");
    request.view.focal_pixels = positive(param, "focal", request.view.focal_pixels);
    request.view.pixel_size = positive(param, "pixel", request.view.pixel_size);
    request.view.budget = std::size_t(positive(param, "budget", double(request.view.budget)));
    if (param("closeup")) request.close_up_triangles = std::size_t(positive(param, "closeup", 1));
    return request;
}

namespace {

void put_node(std::string& out, const SplatNode& n) {
    put_floats(out, {n.centre[0], n.centre[1], n.centre[2], n.normal[0], n.normal[1], n.normal[2], n.radius});
}

}  // namespace

std::string splat_buffers(const SplatTree& tree, const SplatSelection& selection) {
    std::string out;
    out.reserve(28 * selection.nodes.size());
    for (std::uint32_t i : selection.nodes) put_node(out, tree.nodes[i]);
    return out;
}

std::string splat_buffers(const std::vector<SplatNode>& nodes) {
    std::string out;
    out.reserve(28 * nodes.size());
    for (const SplatNode& n : nodes) put_node(out, n);
    return out;
}

SplatStore::SplatStore(std::shared_ptr<const ViewScan> scan, std::shared_ptr<const ViewSplats> initial, double initial_iso,
                       std::uint64_t other_max_bytes)
    : scan_(std::move(scan)), initial_iso_(initial_iso), other_max_bytes_(other_max_bytes) {
    if (initial) set_initial(std::move(initial));
}

void SplatStore::set_initial(std::shared_ptr<const ViewSplats> splats) {
    auto stored = std::make_shared<const StoredSplats>(StoredSplats{splats->tree, splats->seconds, splats->preview});
    const std::lock_guard<std::mutex> lock(initial_mutex_);
    initial_splats_ = std::move(splats);
    initial_ = std::move(stored);
}

std::shared_ptr<const ViewSplats> SplatStore::initial() const {
    const std::lock_guard<std::mutex> lock(initial_mutex_);
    return initial_splats_;
}

std::shared_ptr<const StoredSplats> SplatStore::tree(double iso) {
    std::shared_ptr<const StoredSplats> initial;
    {
        const std::lock_guard<std::mutex> lock(initial_mutex_);
        initial = initial_;
    }
    if (initial && iso == initial_iso_) return initial;
    const auto scan = std::atomic_load(&scan_);
    if (!scan && initial) throw ScanPreparing();
    if (!scan) throw UsageError("splats: the input is a mesh, not a scan or grid");
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [kept_iso, stored] : kept_)
        if (kept_iso == iso) return stored;
    if (other_max_bytes_ != 0) kept_.clear();  // within a bound: the new tree in place of the kept one
    const auto start = std::chrono::steady_clock::now();
    auto stored = std::make_shared<StoredSplats>();
    SplatOptions options;
    options.iso = iso;
    options.max_bytes = other_max_bytes_;
    // The same tree either way; a grid read by region is read one node at a time.
    stored->tree = std::make_shared<const SplatTree>(scan->grid ? build_splat_tree(*scan->grid, options)
                                                                : build_splat_tree(*scan->regions, options));
    stored->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    kept_.emplace_front(iso, stored);
    if (kept_.size() > kKept) kept_.pop_back();
    return stored;
}

}  // namespace vdbmesh::view
