#pragma once
/// @file mesh_refusals.h
/// @brief The words `vdbmesh mesh` and the Python module's mesh() refuse mesh settings with,
/// kept in one place so that both refuse the same cases alike: the settings MeshOptions::sharp
/// does not go with, and the triangle budgets mesh_to_budget() cannot meet. Each front end
/// spells its options its own way (OptionStyle).

#include <cstdint>
#include <string>

#include "vdbmesh/mesh_budget.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh {

/// How a front end spells an option with its value: "--error 0" (command line) or "error=0" (Python).
enum class OptionStyle { command_line, python };

/// Why MeshOptions::sharp cannot be asked with @a method, @a error and (@a budget) a triangle
/// budget: "--sharp: only with --error above 0 (at 0 no cell merges), got --error 0" (Python:
/// "sharp=True: only with error above 0 ..., got error=0"); empty when it can (or @a sharp is
/// false). The checks in `vdbmesh mesh`'s order: the method, the error, the budget.
std::string sharp_refusal(OptionStyle style, bool sharp, MeshMethod method, double error, bool budget);

/// Why mesh_to_budget() did not meet the budget @a triangles with its mesh of @a got triangles
/// and @a report: above the error-0 mesh's triangles, or below where the decimator had to stop;
/// "--triangles N: the most accurate mesh there is (--error 0) has ..." (Python: "triangles=N:
/// ... (error=0) ..."). Empty when it was met, or there is no surface (@a got 0).
std::string budget_refusal(OptionStyle style, std::uint64_t triangles, std::size_t got, const BudgetReport& report);

}  // namespace vdbmesh
