// mesh_to_budget(): DC at an error picked from the budget, then the guaranteed decimator down to
// it (mesh_budget.h). Measured against volumeToMesh at adaptivity 1 in bench/README.md, "Triangle budget".
#include <array>
#include <chrono>

#include "vdbmesh/error.h"
#include "vdbmesh/mesh_budget.h"

namespace vdbmesh {
namespace {

/// The errors between kBudgetBaseError and 0, coarsest first: DC's triangle count grows along
/// them (nearly everywhere: the walnut's error 0.1 has more triangles than its error 0).
constexpr std::array<double, 4> kBetweenErrors{1, 0.5, 0.25, 0.1};

MeshResult dc_mesh(const openvdb::FloatGrid& grid, MeshOptions options, double error) {
    options.method = MeshMethod::dc;
    options.error = error;
    return mesh_grid(grid, options);
}

/// The most accurate mesh that fits, given @a fitting at kBudgetBaseError that does, in
/// @a report: the error-0 mesh (Marching Cubes', the quickest to make) when it fits, else the
/// smallest of kBetweenErrors whose mesh fits, found by bisection (two or three meshes, not up
/// to four one after the other), else @a fitting.
MeshResult most_accurate_fitting(const openvdb::FloatGrid& grid, const MeshOptions& options, std::size_t max_triangles,
                                 MeshResult fitting, BudgetReport& report) {
    if (fitting.mesh.triangles.empty()) return fitting;  // no surface: none at a smaller error either
    const auto take_if_fits = [&](double error) {
        MeshResult finer = dc_mesh(grid, options, error);
        if (finer.mesh.triangles.size() > max_triangles) return false;
        report.error = error;
        report.meshed_triangles = finer.mesh.triangles.size();
        fitting = std::move(finer);
        return true;
    };
    if (take_if_fits(0)) return fitting;
    // Bisection: kBetweenErrors[fits] fits (-1: the base error), kBetweenErrors[fails] does not
    // (the size: error 0).
    int fits = -1, fails = int(kBetweenErrors.size());
    while (fails - fits > 1) {
        const int middle = (fits + fails) / 2;
        (take_if_fits(kBetweenErrors[std::size_t(middle)]) ? fits : fails) = middle;
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
