#include "view/mesh_store.h"

#include <utility>

namespace vdbmesh::view {

MeshStore::MeshStore(ViewSource source, GridMesher mesher)
    : source_(std::move(source)), mesher_(mesher ? std::move(mesher) : GridMesher(mesh_grid)) {}

std::shared_ptr<StoredMesh> MeshStore::mesh(const MeshRequest& request) {
    const std::string key = source_.mesh ? "file" : request.key();
    const std::uint64_t coarse_seen = request.level == MeshLevel::coarse ? ++coarse_requests_ : coarse_requests_.load();
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [kept_key, stored] : kept_) {
        if (kept_key == key) return stored;
    }
    auto stored = make(request, coarse_seen);
    kept_.emplace_front(key, stored);
    if (kept_.size() > kKept) kept_.pop_back();
    return stored;
}

std::shared_ptr<StoredMesh> MeshStore::make(const MeshRequest& request, std::uint64_t coarse_seen) const {
    auto stored = std::make_shared<StoredMesh>();
    if (source_.mesh) {
        stored->mesh = source_.mesh;
        return stored;
    }
    const bool coarse = request.level == MeshLevel::coarse;
    MeshOptions options = request.options;
    if (coarse) options.method = MeshMethod::mc;
    auto give_up_when_superseded = [this, coarse_seen](double) {
        if (coarse_requests_ != coarse_seen) throw Superseded();
    };
    if (!coarse) {
        give_up_when_superseded(0);
        options.progress = give_up_when_superseded;
    }
    MeshResult result = mesher_(coarse ? *source_.scan->coarse : *source_.scan->grid, options);
    stored->mesh = std::make_shared<const Mesh>(std::move(result.mesh));
    stored->seconds = result.report.total_seconds();
    return stored;
}

const std::string& StoredMesh::figures(const std::function<std::string(const Mesh&)>& describe) {
    std::call_once(figures_once_, [&] { figures_ = describe ? describe(*mesh) : "{}"; });
    return figures_;
}

}  // namespace vdbmesh::view
