// mesh_to_budget(): DC at an error picked from the budget, then the guaranteed decimator down to
// it (mesh_budget.h). Measured against volumeToMesh at adaptivity 1 in bench/README.md, "Triangle budget".
#include <array>
#include <chrono>

#include "vdbmesh/error.h"
#include "vdbmesh/mesh_budget.h"

namespace vdbmesh {
namespace {

/// The errors tried below kBudgetBaseError when its mesh fits and the error-0 mesh does not,
/// most accurate last.
constexpr std::array<double, 4> kSmallerErrors{1, 0.5, 0.25, 0.1};

MeshResult dc_mesh(const openvdb::FloatGrid& grid, MeshOptions options, double error) {
    options.method = MeshMethod::dc;
    options.error = error;
    return mesh_grid(grid, options);
}

/// The most accurate of the smaller errors' meshes that fits (@a fitting, at kBudgetBaseError,
/// when none does), in @a report. The error-0 mesh (Marching Cubes', the quickest to make) is
/// tried first: when it fits, no other is made.
MeshResult most_accurate_fitting(const openvdb::FloatGrid& grid, const MeshOptions& options, std::size_t max_triangles,
                                 MeshResult fitting, BudgetReport& report) {
    if (fitting.mesh.triangles.empty()) return fitting;  // no surface: none at a smaller error either
    MeshResult finest = dc_mesh(grid, options, 0);
    if (finest.mesh.triangles.size() <= max_triangles) {
        report.error = 0;
        report.meshed_triangles = finest.mesh.triangles.size();
        return finest;
    }
    for (const double error : kSmallerErrors) {
        MeshResult finer = dc_mesh(grid, options, error);
        const std::size_t triangles = finer.mesh.triangles.size();
        if (triangles > max_triangles) break;
        fitting = std::move(finer);
        report.error = error;
        report.meshed_triangles = triangles;
    }
    return fitting;
}

}  // namespace

MeshResult mesh_to_budget(const openvdb::FloatGrid& grid, const MeshOptions& options, std::size_t max_triangles, BudgetReport* report) {
    if (max_triangles == 0) throw UsageError("--triangles: expected a budget of at least 1 triangle, got 0");
    if (options.open_boundary) throw UsageError("--triangles: the decimation needs a closed surface, got --open-boundary");
    BudgetReport local;
    MeshResult result = dc_mesh(grid, options, kBudgetBaseError);
    local.error = kBudgetBaseError;
    local.meshed_triangles = result.mesh.triangles.size();
    if (local.meshed_triangles <= max_triangles) {
        result = most_accurate_fitting(grid, options, max_triangles, std::move(result), local);
    } else {
        DecimateOptions decimate;
        decimate.target_triangles = max_triangles;
        const auto start = std::chrono::steady_clock::now();
        result.mesh = decimate_mesh(result.mesh, decimate, &local.decimate);
        result.report.phases.push_back({"decimate", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
    }
    if (report) *report = local;
    return result;
}

}  // namespace vdbmesh
