#pragma once
// What `vdbmesh similarity` and `vdbmesh classify` share.

#include <CLI/CLI.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "vdbmesh/points.h"

namespace vdbmesh::cli {

struct SolidOptions {
    int neighbours = 16;
};

/// Reads points, drops outliers, estimates normals when missing; fits the field when asked.
PointCloud load_solid(const std::string& path, const SolidOptions& options, std::unique_ptr<RbfField>* field);
void add_solid_options(CLI::App& command, SolidOptions& solid, SimilarityOptions& sim);
nlohmann::ordered_json similarity_json(const SimilarityResult& r);

}  // namespace vdbmesh::cli
