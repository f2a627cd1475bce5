#pragma once
/// @file mesh_budget.h
/// @brief A triangle budget (`vdbmesh mesh --triangles N`): the closest mesh of a grid's
/// isosurface with at most N triangles that is still closed, manifold, outward and free of
/// self-intersections. DC at an error picked from N, then, when that mesh has more than N
/// triangles, decimate_mesh() (process.h) down to N. OpenVDB-free: the grid is only declared.

#include <cstddef>

#include "vdbmesh/mesher.h"
#include "vdbmesh/openvdb_fwd.h"
#include "vdbmesh/process.h"

namespace vdbmesh {

/// The DC error (voxels) a budget starts from: about DC's lightest mesh (errors above add few
/// fewer triangles: bunny CT 559,996 at 2, 553,028 at 8), so a smaller budget is left to the
/// decimator from here, with the least to remove. Starting at error 1 instead (bunny CT 583,492
/// triangles, 0.97 voxel from the surface against 1.74) was measured as the other route: closer
/// to the surface after the decimation, but 4-35% slower and with more small angles
/// (bench/README.md, "Triangle budget").
inline constexpr double kBudgetBaseError = 2.0;

/// What mesh_to_budget() did.
struct BudgetReport {
    double error = 0;                   ///< the DC error of the mesh it kept or decimated
    std::size_t meshed_triangles = 0;   ///< that mesh's triangles
    DecimateReport decimate;            ///< what the decimation did (no collapses when that mesh fit)
};

/// @brief The mesh of @a grid (options.iso, inside, open_boundary; options.method and error are
/// ignored) with at most @a max_triangles triangles, closest to the surface by this route: DC at
/// kBudgetBaseError; when it has more triangles than the budget, decimated by decimate_mesh() to
/// the budget (a phase "decimate" in the report); when it has no more, the error-0 mesh if it
/// fits, else the mesh of the smallest of the errors 1, 0.5, 0.25, 0.1 that fits, found by
/// bisection (DC's triangle count grows as the error shrinks, nearly everywhere).
/// Every guarantee of DC holds: the decimator keeps them. The same mesh for any thread count.
/// Two budgets cannot be met as asked, and `vdbmesh mesh --triangles` refuses both: one above
/// the error-0 mesh's triangles gives that mesh (report->error 0, fewer triangles than the
/// budget); one below what the decimator can reach keeping the guarantees gives the mesh where
/// it stopped (more triangles than the budget: each further collapse would break one).
/// @throw UsageError for max_triangles 0 or options.open_boundary (the decimator needs a closed
/// surface).
MeshResult mesh_to_budget(const openvdb::FloatGrid& grid, const MeshOptions& options, std::size_t max_triangles,
                          BudgetReport* report = nullptr);

}  // namespace vdbmesh
