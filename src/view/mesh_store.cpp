#include "view/mesh_store.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include "view/region_mesh.h"

namespace vdbmesh::view {

namespace {

/// The full mesh of a grid read by region: by bricks within @a memory_bytes where the method
/// allows (DC at an error > 0), else read whole. The mesh itself is held whole either way.
MeshResult whole_by_region(const GridRegionSource& regions, const MeshOptions& options, std::uint64_t memory_bytes) {
    BrickOptions bricks;
    if (options.method == MeshMethod::dc && options.error > 0) bricks.memory_bytes = memory_bytes;
    return mesh_bricks(regions, options, bricks);
}

}  // namespace

MeshStore::MeshStore(ViewSource source, GridMesher mesher, std::size_t triangle_budget, std::uint64_t region_read_bytes)
    : source_(std::move(source)),
      mesher_(mesher ? std::move(mesher) : GridMesher(mesh_grid)),
      triangle_budget_(triangle_budget),
      region_read_bytes_(region_read_bytes) {}

std::size_t MeshStore::estimated_full_triangles(const ViewScan& scan, const MeshRequest& request) const {
    MeshOptions options = request.options;
    options.method = MeshMethod::mc;
    const std::size_t coarse = mesher_(*scan.coarse, options).mesh.triangles.size();
    const auto factor = std::size_t(scan.coarse_factor);
    return coarse * factor * factor;
}

std::shared_ptr<const ViewScan> MeshStore::prepared_scan() const {
    auto prepared = scan();
    if (!prepared) throw ScanPreparing();
    return prepared;
}

std::shared_ptr<StoredMesh> MeshStore::mesh(const MeshRequest& request) {
    if (!source_.mesh && !scan()) throw ScanPreparing();
    if (const auto prepared = scan(); request.level == MeshLevel::full && prepared && !prepared->grid) {
        const std::size_t estimate = estimated_full_triangles(*prepared, request);
        if (estimate > triangle_budget_) throw FullMeshOverBudget(estimate);
    }
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
    const auto scan = prepared_scan();
    if (request.level == MeshLevel::region) {
        const auto start = std::chrono::steady_clock::now();
        stored->mesh = std::make_shared<const Mesh>(region_mesh(*scan->regions, request.box, request.options, region_read_bytes_));
        stored->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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
    MeshResult result = coarse || scan->grid ? mesher_(coarse ? *scan->coarse : *scan->grid, options)
                                             : whole_by_region(*scan->regions, options, std::min(kWholeMeshMemory, region_read_bytes_));
    stored->mesh = std::make_shared<const Mesh>(std::move(result.mesh));
    stored->seconds = result.report.total_seconds();
    return stored;
}

const std::string& StoredMesh::figures(const std::function<std::string(const Mesh&)>& describe) {
    std::call_once(figures_once_, [&] { figures_ = describe ? describe(*mesh) : "{}"; });
    return figures_;
}

}  // namespace vdbmesh::view
