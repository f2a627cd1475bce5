// mesh_grid(): checks the options, hands the grid to the chosen mesher, and keeps the
// triangles counter-clockwise seen from outside in world space.

#include <cmath>
#include <string>
#include <utility>

#include "mesh/ifc.h"
#include "mesh/marching_cubes.h"
#include "mesh/mesh_phases.h"
#include "mesh/openvdb_mesher.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh {

namespace {

void check_options(const MeshOptions& options) {
    if (!std::isfinite(options.iso)) throw UsageError("isovalue: expected a finite number, got " + std::to_string(options.iso));
    if (!(options.error >= 0) || !std::isfinite(options.error)) {
        throw UsageError("error: expected a finite number >= 0, got " + std::to_string(options.error));
    }
    if (!(options.adaptivity >= 0 && options.adaptivity <= 1)) {
        throw UsageError("adaptivity: expected a number in [0, 1], got " + std::to_string(options.adaptivity));
    }
    if (options.open_boundary && options.method == MeshMethod::openvdb) {
        throw UsageError("open boundary: not available with the openvdb method (volumeToMesh meshes the grid's values as they are)");
    }
    if (options.open_boundary && options.method == MeshMethod::dc) {
        throw UsageError("open boundary: not available with the dc method (its cells close the surface)");
    }
}

Mesh run_mesher(const openvdb::FloatGrid& grid, const MeshOptions& options, MeshReport& report) {
    switch (options.method) {
        case MeshMethod::mc:
            return detail::marching_cubes(grid, options);
        case MeshMethod::openvdb:
            return detail::openvdb_volume_to_mesh(grid, options);
        case MeshMethod::dc:
            return detail::intersection_free_contouring(grid, options, report);
    }
    throw UsageError("mesh method: unknown value " + std::to_string(int(options.method)));
}

/// Whether the index-to-world map mirrors space (x-flipped scans): its linear part has a
/// negative determinant. The meshers orient triangles in index space, so the world then sees
/// them wound the other way.
bool mirrors(const openvdb::math::Transform& transform) {
    return transform.baseMap()->getAffineMap()->getMat4().getMat3().det() < 0;
}

}  // namespace

double MeshReport::total_seconds() const {
    double total = 0;
    for (const MeshPhase& phase : phases) total += phase.seconds;
    return total;
}

MeshResult mesh_grid(const openvdb::FloatGrid& grid, const MeshOptions& options) {
    check_options(options);
    MeshResult result;
    MeshReport& report = result.report;
    report = {options.method, options.iso, options.error, options.adaptivity, options.inside, options.open_boundary, {}, {}};
    detail::PhaseClock clock;
    result.mesh = run_mesher(grid, options, report);
    // Meshers that time no phases of their own are one phase.
    if (report.phases.empty()) clock.lap(report, "mesh");
    if (mirrors(grid.transform())) {
        for (auto& triangle : result.mesh.triangles) std::swap(triangle[1], triangle[2]);
    }
    return result;
}

}  // namespace vdbmesh
