#pragma once
// The figures of `vdbmesh check` as JSON, shared by `check` and `compare`; a mesher's phases,
// shared by `mesh` and `compare`.

#include <nlohmann/json.hpp>

#include "vdbmesh/analysis.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::cli {

/// Every field of @a report (and "clean"), in a fixed order.
nlohmann::ordered_json report_json(const MeshAnalysis& report);

/// The mesher's phases in the order run: [{"name", "seconds"}, ...].
nlohmann::ordered_json phases_json(const MeshReport& report);

}  // namespace vdbmesh::cli
