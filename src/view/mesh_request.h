#pragma once
// What GET /api/mesh, /api/figures and /api/download ask for, from their query parameters.

#include <functional>
#include <optional>
#include <string>

#include "vdbmesh/mesher.h"

namespace vdbmesh::view {

/// coarse: the coarse grid with Marching Cubes, whatever the method; full: the full grid.
enum class MeshLevel { coarse, full };

/// What a request asks for (a mesh file ignores all but the level).
struct MeshRequest {
    MeshLevel level = MeshLevel::full;
    MeshOptions options;
    /// GET /api/mesh: answer 413 instead of the buffers when the mesh has more triangles.
    std::optional<std::size_t> max_triangles;
    /// Equal for requests that give the same mesh.
    std::string key() const;
};

/// The value of a query parameter, none when absent.
using ParamLookup = std::function<std::optional<std::string>(const std::string& name)>;

/// @a text as a finite number. @throw UsageError naming @a parameter otherwise.
double number_param(const std::string& parameter, const std::string& text);

/// level=coarse|full (full), method=dc|mc|openvdb (dc), iso (@a default_iso), error (0),
/// adaptivity (0), max_triangles (none). @throw UsageError naming the parameter for a value it cannot take.
MeshRequest parse_mesh_request(const ParamLookup& param, double default_iso);

}  // namespace vdbmesh::view
