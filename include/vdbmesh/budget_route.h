#pragma once
/// @file budget_route.h
/// @brief Which DC meshes mesh_to_budget() makes for a budget, and which one it keeps, given
/// their triangle counts: the route in one place, for mesh_to_budget() and for compare_meshers(),
/// which has made those meshes already (as its DC rows) and so needs not make them again.

#include <cstddef>
#include <functional>
#include <optional>

namespace vdbmesh {

/// mesh_to_budget()'s route for @a max_triangles: DC's mesh at kBudgetBaseError; when it fits,
/// the error-0 mesh if that fits, else the smallest of the errors 1, 0.5, 0.25, 0.1 whose mesh
/// fits, by bisection. @a triangles_at(error) makes (or looks up) DC's mesh at that error and
/// returns its triangles; it is called in the order mesh_to_budget() meshes. Returns the error
/// of the mesh kept; empty when the kBudgetBaseError mesh has more triangles than the budget
/// (mesh_to_budget() then decimates it). A mesh of no triangles (no surface) is kept at once.
std::optional<double> budget_route(std::size_t max_triangles, const std::function<std::size_t(double)>& triangles_at);

}  // namespace vdbmesh
