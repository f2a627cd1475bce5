// mesh_to_budget(): DC at an error picked from the budget, then the guaranteed decimator down to
// it (mesh_budget.h). Measured against volumeToMesh at adaptivity 1 in bench/README.md, "Triangle budget".
#include <array>
#include <chrono>
#include <functional>
#include <optional>

#include "vdbmesh/budget_route.h"
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

}  // namespace

std::optional<double> budget_route(std::size_t max_triangles, const std::function<std::size_t(double)>& triangles_at) {
    const std::size_t base = triangles_at(kBudgetBaseError);
    if (base > max_triangles) return std::nullopt;
    if (base == 0) return kBudgetBaseError;  // no surface: none at a smaller error either
    // The error-0 mesh (Marching Cubes', the quickest to make) when it fits, else bisection:
    // two or three meshes, not up to four one after the other.
    if (triangles_at(0) <= max_triangles) return 0.0;
    // kBetweenErrors[fits] fits (-1: the base error), kBetweenErrors[fails] does not (the size: error 0).
    int fits = -1, fails = int(kBetweenErrors.size());
    while (fails - fits > 1) {
        const int middle = (fits + fails) / 2;
        (triangles_at(kBetweenErrors[std::size_t(middle)]) <= max_triangles ? fits : fails) = middle;
    }
    return fits < 0 ? kBudgetBaseError : kBetweenErrors[std::size_t(fits)];
}

MeshResult mesh_to_budget(const openvdb::FloatGrid& grid, const MeshOptions& options, std::size_t max_triangles, BudgetReport* report) {
    if (max_triangles == 0) throw UsageError("--triangles: expected a budget of at least 1 triangle, got 0");
    if (options.open_boundary) throw UsageError("--triangles: the decimation needs a closed surface, got --open-boundary");
    BudgetReport local;
    MeshResult result;
    // Keeps the latest mesh that fits, and first the base mesh (which the decimator starts from
    // when it does not fit).
    const auto triangles_at = [&](double error) {
        MeshResult mesh = dc_mesh(grid, options, error);
        const std::size_t count = mesh.mesh.triangles.size();
        if (count <= max_triangles || error == kBudgetBaseError) {
            local.error = error;
            local.meshed_triangles = count;
            result = std::move(mesh);
        }
        return count;
    };
    if (!budget_route(max_triangles, triangles_at)) {
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
