#include "view/mesh_store.h"

#include <chrono>


namespace vdbmesh::view {

MeshStore::MeshStore(ViewSource source) : source_(std::move(source)) {}

std::shared_ptr<StoredMesh> MeshStore::mesh(const MeshRequest& request) {
    const std::string key = source_.mesh ? "file" : request.key();
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [kept_key, stored] : kept_) {
        if (kept_key == key) return stored;
    }
    auto stored = make(request);
    kept_.emplace_front(key, stored);
    if (kept_.size() > kKept) kept_.pop_back();
    return stored;
}

std::shared_ptr<StoredMesh> MeshStore::make(const MeshRequest& request) const {
    auto stored = std::make_shared<StoredMesh>();
    if (source_.mesh) {
        stored->mesh = source_.mesh;
        return stored;
    }
    const bool coarse = request.level == MeshLevel::coarse;
    MeshOptions options = request.options;
    if (coarse) options.method = MeshMethod::mc;
    const auto start = std::chrono::steady_clock::now();
    stored->mesh = std::make_shared<const Mesh>(mesh_grid(coarse ? *source_.scan->coarse : *source_.scan->grid, options));
    stored->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stored;
}

const std::string& StoredMesh::figures(const std::function<std::string(const Mesh&)>& describe) {
    std::call_once(figures_once_, [&] { figures_ = describe ? describe(*mesh) : "{}"; });
    return figures_;
}

}  // namespace vdbmesh::view
