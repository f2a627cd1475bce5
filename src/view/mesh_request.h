#pragma once
// What GET /api/mesh, /api/figures and /api/download ask for, from their query parameters.

#include <array>
#include <functional>
#include <optional>
#include <sstream>
#include <string>

#include "vdbmesh/error.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::view {

/// coarse: the coarse grid with Marching Cubes, whatever the method; full: the full grid;
/// region: the full mesh's triangles with a corner in a box (region_mesh.h).
enum class MeshLevel { coarse, full, region };

/// What a request asks for (a mesh file ignores all but the level).
struct MeshRequest {
    MeshLevel level = MeshLevel::full;
    MeshOptions options;
    /// GET /api/mesh: answer 413 instead of the buffers when the mesh has more triangles.
    std::optional<std::size_t> max_triangles;
    /// level=region: the box, in the grid's index space (voxels; min inclusive, max exclusive).
    IndexBox box;
    /// Equal for requests that give the same mesh.
    std::string key() const;
};

/// The value of a query parameter, none when absent.
using ParamLookup = std::function<std::optional<std::string>(const std::string& name)>;

/// @a text as a finite number. @throw UsageError naming @a parameter otherwise.
double number_param(const std::string& parameter, const std::string& text);

/// The comma-separated numbers of @a parameter, exactly @a count of them.
template <std::size_t count>
std::array<double, count> number_params(const ParamLookup& param, const std::string& parameter) {
    const auto text = param(parameter);
    if (!text) throw UsageError(parameter + ": expected " + std::to_string(count) + " comma-separated numbers, got nothing");
    std::array<double, count> values{};
    std::stringstream in(*text);
    std::string item;
    std::size_t n = 0;
    while (std::getline(in, item, ',')) {
        if (n == count) break;
        values[n++] = number_param(parameter, item);
    }
    if (n != count || in.good())
        throw UsageError(parameter + ": expected " + std::to_string(count) + " comma-separated numbers, got \"" + *text + "\"");
    return values;
}

/// level=coarse|full|region (full), box (x0,y0,z0,x1,y1,z1, whole voxels, each max above its min:
/// required for region and only with it), method=dc|mc|openvdb (dc), iso (@a default_iso), error (0),
/// adaptivity (0), max_triangles (none). @throw UsageError naming the parameter for a value it cannot take.
MeshRequest parse_mesh_request(const ParamLookup& param, double default_iso);

}  // namespace vdbmesh::view
