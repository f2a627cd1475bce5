#pragma once
// The figures of `vdbmesh check` as JSON, shared by `check` and `compare`.

#include <nlohmann/json.hpp>

#include "vdbmesh/analysis.h"

namespace vdbmesh::cli {

/// Every field of @a report (and "clean"), in a fixed order.
nlohmann::ordered_json report_json(const MeshAnalysis& report);

}  // namespace vdbmesh::cli
