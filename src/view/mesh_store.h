#pragma once
// The meshes the page asks for: made through the library on request (one at a time, the
// machine's cores all go to it), the last few kept so that the buffers, the figures and a
// download of the same mesh cost one meshing.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "vdbmesh/view.h"
#include "view/mesh_request.h"

namespace vdbmesh::view {

/// A mesh made for the page, and its figures once asked for.
struct StoredMesh {
    std::shared_ptr<const Mesh> mesh;
    double seconds = 0;  ///< the mesher's time, its phases summed (0 for a mesh file)
    /// The figures of the mesh by @a describe (JSON text), computed on the first call.
    const std::string& figures(const std::function<std::string(const Mesh&)>& describe);

private:
    std::once_flag figures_once_;
    std::string figures_;
};

/// Thrown when a full mesh is given up because the page asked for a newer coarse one.
class Superseded : public std::runtime_error {
public:
    Superseded() : std::runtime_error("superseded: a newer isovalue or method was asked for") {}
};

/// Thrown while the scan is still being prepared in the background (ViewSource::prepare_scan).
class ScanPreparing : public std::runtime_error {
public:
    ScanPreparing() : std::runtime_error("the scan's histogram and coarse grid are being prepared: the splats are shown meanwhile") {}
};

/// Thrown instead of making the full mesh of a grid read by region (a model too large to hold)
/// whose estimated triangles exceed the budget: the page shows splats and close-ups instead.
class FullMeshOverBudget : public std::runtime_error {
public:
    explicit FullMeshOverBudget(std::size_t estimate)
        : std::runtime_error("the full mesh of a grid read by region is made only within the triangle budget (--budget); "
                             "this one has about " + std::to_string(estimate) + " triangles: zoom in for triangles, or use `vdbmesh mesh --memory`"),
          estimate(estimate) {}
    std::size_t estimate;
};

/// The memory the bricks of a full mesh of a grid read by region may take (the mesh aside),
/// or one close-up's read when less (ViewServerOptions::region_read_bytes: `view --memory`).
inline constexpr std::uint64_t kWholeMeshMemory = std::uint64_t(1) << 30;

class MeshStore {
public:
    /// Meshes with @a mesher, mesh_grid() when empty; a grid read by region only within
    /// @a triangle_budget, its close-ups each reading at most @a region_read_bytes.
    MeshStore(ViewSource source, GridMesher mesher, std::size_t triangle_budget, std::uint64_t region_read_bytes);
    /// The source as given (never changed; its scan null when prepared later: see scan()).
    const ViewSource& source() const { return source_; }
    /// The scan: the source's, else the one prepare_scan made (null until then).
    std::shared_ptr<const ViewScan> scan() const { return source_.scan ? source_.scan : std::atomic_load(&prepared_); }
    /// The scan prepare_scan made.
    void set_scan(std::shared_ptr<const ViewScan> scan) { std::atomic_store(&prepared_, std::move(scan)); }
    /// The mesh of @a request, made now unless kept. A coarse request is the page's first
    /// of a new setting: full meshes asked for before it stop at the mesher's next progress
    /// report (Superseded), so that the new one does not wait for them.
    /// @throw UsageError for options the mesher refuses, Superseded, FullMeshOverBudget.
    std::shared_ptr<StoredMesh> mesh(const MeshRequest& request);

private:
    static constexpr std::size_t kKept = 4;
    std::shared_ptr<StoredMesh> make(const MeshRequest& request, std::uint64_t coarse_seen) const;
    /// The scan, or ScanPreparing.
    std::shared_ptr<const ViewScan> prepared_scan() const;
    /// The triangles of the full mesh of a grid read by region, estimated without making it:
    /// the coarse grid's Marching Cubes triangles times the coarse factor squared (a surface's
    /// triangles grow as the square of the resolution).
    std::size_t estimated_full_triangles(const ViewScan& scan, const MeshRequest& request) const;

    ViewSource source_;
    std::shared_ptr<const ViewScan> prepared_;  ///< set once by set_scan(), read atomically
    GridMesher mesher_;
    std::size_t triangle_budget_;
    std::uint64_t region_read_bytes_;
    std::atomic<std::uint64_t> coarse_requests_{0};
    std::mutex mutex_;
    std::deque<std::pair<std::string, std::shared_ptr<StoredMesh>>> kept_;  ///< newest first
};

}  // namespace vdbmesh::view
