// Dual Marching Cubes on the VDB tree: the driver. Octrees per leaf (dmc_octree.cpp), dual
// cells (dmc_dual_cells.cpp), Marching Cubes on them (dmc_contour.cpp), then the self-check
// (dmc_self_check.cpp) and the coverage check (dmc_coverage_check.cpp): merged cells behind
// self-intersecting, non-manifold or inaccurate triangles, or holding isosurface the mesh
// strays from, are split into their children and the surface remade, until none remain.

#include "mesh/dmc.h"

#include <algorithm>
#include <string>

#include "mesh/dmc_contour.h"
#include "mesh/dmc_coverage_check.h"
#include "mesh/dmc_grid.h"
#include "mesh/dmc_octree.h"
#include "mesh/dmc_self_check.h"
#include "mesh/mesh_phases.h"

namespace vdbmesh::detail {

namespace {

/// Far above what the meshes tried need (2 to 5 rounds); past it, Marching Cubes is returned.
constexpr int kMaxRefinementRounds = 32;

bool any_merged(const std::vector<LeafOctree>& octrees) {
    return std::any_of(octrees.begin(), octrees.end(), [](const LeafOctree& o) { return o.has_merges(); });
}

}  // namespace

Mesh dual_marching_cubes(const openvdb::FloatGrid& grid, const MeshOptions& options, MeshReport& mesh_report) {
    auto report = [&](double fraction) {
        if (options.progress) options.progress(fraction);
    };
    PhaseClock clock;
    const DmcGrid dmc_grid = make_dmc_grid(grid, options);
    std::vector<LeafOctree> octrees = build_leaf_octrees(dmc_grid, options.error);
    clock.lap(mesh_report, "octree");
    report(0.3);
    if (!any_merged(octrees)) {
        Mesh mesh = contour_dual_cells(dmc_grid, octrees, false, [&](double f) { report(0.3 + 0.7 * f); }).mesh;
        clock.lap(mesh_report, "contour");
        return mesh;
    }
    // Chords of merged cells may stray up to twice the QEF tolerance from the isosurface.
    const double tolerance = 2.0 * options.error;
    // The first check judges the triangles of merged cells, later ones only those next to the
    // cells split since, and only the leaves next to those are contoured again.
    SplitVoxels split;
    DmcContourCache cache;
    for (int round = 0;; ++round) {
        if (round > 0) cache.changed = split.changed;
        DmcContour contour = contour_dual_cells(dmc_grid, octrees, true, {}, &cache);
        clock.lap(mesh_report, "contour");
        report(0.3 + 0.7 * std::min(1.0, (round + 1) / 4.0));
        if (!any_merged(octrees)) return std::move(contour.mesh);
        const SplitVoxels* since = round == 0 ? nullptr : &split;
        mesh_report.refinement_rounds = round + 1;
        const std::vector<std::uint32_t> refine = triangles_to_refine(dmc_grid, contour, tolerance, since);
        const std::vector<LeafVoxel> uncovered = cells_missing_surface(dmc_grid, octrees, contour, tolerance, since);
        const bool refined = split_cells_of(dmc_grid, contour, refine, octrees, split);  // resets split
        const bool split_any = split_cells_at(uncovered, octrees, split) || refined;
        clock.lap(mesh_report, "check");
        if (!split_any) return std::move(contour.mesh);
        if (round + 1 == kMaxRefinementRounds) break;
    }
    // Still not clean after all the rounds: Marching Cubes, which always is.
    mesh_report.fallbacks.push_back("Marching Cubes: the DMC mesh was not clean after " +
                                    std::to_string(kMaxRefinementRounds) + " refinement rounds");
    for (LeafOctree& octree : octrees) octree = LeafOctree();
    Mesh mesh = contour_dual_cells(dmc_grid, octrees, false, {}).mesh;
    clock.lap(mesh_report, "contour");
    return mesh;
}

Mesh dual_marching_cubes(const openvdb::FloatGrid& grid, const MeshOptions& options) {
    MeshReport report;
    return dual_marching_cubes(grid, options, report);
}

}  // namespace vdbmesh::detail
