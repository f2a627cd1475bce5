#pragma once
// The JSON of GET /api/info: what the page shows.

#include <cstddef>

#include <nlohmann/json.hpp>

#include "vdbmesh/view.h"

namespace vdbmesh::view {

/// The input's name and kind; for scans the value range, histogram, suggested and initial
/// isovalue and the coarse factor; the triangle budget.
nlohmann::json info_json(const ViewSource& source, std::size_t triangle_budget);

}  // namespace vdbmesh::view
