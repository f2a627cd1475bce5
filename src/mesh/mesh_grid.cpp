// mesh_grid(): checks the options, hands the grid to the chosen mesher, and keeps the
// triangles counter-clockwise seen from outside in world space.

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "mesh/dual_contouring.h"
#include "mesh/dual_surface.h"
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
    if (options.open_boundary && options.method == MeshMethod::dual) {
        throw UsageError("open boundary: not available with the dual method (its cells close the surface)");
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
        case MeshMethod::dual:
            return detail::dual_surface(grid, options, report);
    }
    throw UsageError("mesh method: unknown value " + std::to_string(int(options.method)));
}

/// Whether the index-to-world map mirrors space (x-flipped scans): its linear part has a
/// negative determinant. The meshers orient triangles in index space, so the world then sees
/// them wound the other way.
bool mirrors(const openvdb::math::Transform& transform) {
    return transform.baseMap()->getAffineMap()->getMat4().getMat3().det() < 0;
}

/// Winds @a mesh's triangles counter-clockwise seen from outside in world space: the meshers
/// wind them so in index space.
void orient_outward(const openvdb::math::Transform& transform, Mesh& mesh) {
    if (!mirrors(transform)) return;
    for (auto& triangle : mesh.triangles) std::swap(triangle[1], triangle[2]);
}

/// The box of every node @a source lists, widened by two leaves (the sample windows of the blocks below it): what one brick of the whole grid reads.
IndexBox whole_region(const GridRegionSource& source) {
    IndexBox box{{0, 0, 0}, {0, 0, 0}};
    bool first = true;
    for (const NodeWeight& node : source.nodes()) {
        for (std::size_t a = 0; a < 3; ++a) {
            const std::int32_t lo = node.origin[a] - 16, hi = node.origin[a] + kNodeVoxels + 16;
            box.min[a] = first ? lo : std::min(box.min[a], lo);
            box.max[a] = first ? hi : std::max(box.max[a], hi);
        }
        first = false;
    }
    return box;
}

/// A report of @a options' settings, without phases yet.
MeshReport report_of(const MeshOptions& options) {
    MeshReport report;
    report.method = options.method;
    report.iso = options.iso;
    report.error = options.error;
    report.adaptivity = options.adaptivity;
    report.inside = options.inside;
    report.open_boundary = options.open_boundary;
    return report;
}

void check_brick_options(const MeshOptions& options, const BrickOptions& bricks) {
    check_options(options);
    const BrickShape& shape = bricks.shape;
    const bool in_range = shape.nodes_x >= 1 && shape.nodes_x <= 4096 && shape.nodes_y >= 1 && shape.nodes_y <= 4096;
    if (shape.given() && !in_range) {
        throw UsageError("bricks: expected 1 to 4096 nodes across a brick in x and in y, got " + std::to_string(shape.nodes_x) + " x " +
                         std::to_string(shape.nodes_y));
    }
    if (bricks.ranks < 1 || bricks.rank < 0 || bricks.rank >= bricks.ranks) {
        throw UsageError("bricks: expected rank 0 to " + std::to_string(bricks.ranks - 1) + " of at least 1 rank, got rank " +
                         std::to_string(bricks.rank) + " of " + std::to_string(bricks.ranks));
    }
    if (bricks.ranks > 1 && !bricks.gather) throw UsageError("bricks: a run over several ranks needs their gather");
}

/// @a bricks with a brick size: the one given, else the largest that fits bricks.memory_bytes
/// (else the whole grid's extent); only for the methods that mesh by bricks.
BrickOptions planned_bricks(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks) {
    if (options.method == MeshMethod::openvdb) {
        throw UsageError("bricks: the openvdb method meshes the whole grid at once (volumeToMesh); dc and mc mesh by bricks");
    }
    if (options.method == MeshMethod::dual) throw UsageError("bricks: the dual method (experimental) meshes the whole grid at once; dc and mc mesh by bricks");
    BrickOptions planned = bricks;
    if (!planned.shape.given()) planned.shape = detail::plan_brick_shape(source, bricks.memory_bytes);
    return planned;
}

}  // namespace

MeshReport mesh_bricks_to_stream(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks,
                                 MeshStreamSink& sink) {
    check_brick_options(options, bricks);
    const BrickOptions planned = planned_bricks(source, options, bricks);
    MeshReport report = report_of(options);
    detail::bricked_contouring_to_stream(source, options, planned, mirrors(source.description()->transform()), sink, report);
    return report;
}

double MeshReport::total_seconds() const {
    double total = 0;
    for (const MeshPhase& phase : phases) total += phase.seconds;
    return total;
}

MeshResult mesh_grid(const openvdb::FloatGrid& grid, const MeshOptions& options) {
    check_options(options);
    MeshResult result;
    result.report = report_of(options);
    detail::PhaseClock clock;
    result.mesh = run_mesher(grid, options, result.report);
    // Meshers that time no phases of their own are one phase.
    if (result.report.phases.empty()) clock.lap(result.report, "mesh");
    orient_outward(grid.transform(), result.mesh);
    return result;
}

MeshResult mesh_bricks(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks) {
    check_brick_options(options, bricks);
    if (bricks.ranks > 1) throw UsageError("bricks: a run over several ranks writes its mesh to a stream (mesh_bricks_to_stream())");
    if (!bricks.shape.given() && bricks.memory_bytes == 0) return mesh_grid(*source.read(whole_region(source)), options);
    const BrickOptions planned = planned_bricks(source, options, bricks);
    MeshResult result;
    result.report = report_of(options);
    result.mesh = detail::bricked_contouring(source, options, planned, result.report);
    orient_outward(source.description()->transform(), result.mesh);
    return result;
}

}  // namespace vdbmesh
