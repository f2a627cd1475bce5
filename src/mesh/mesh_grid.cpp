// mesh_grid(): checks the options and hands the grid to the chosen mesher.

#include <cmath>
#include <string>

#include "mesh/dmc.h"
#include "mesh/marching_cubes.h"
#include "mesh/openvdb_mesher.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh {

namespace {

void check_options(const MeshOptions& options) {
    if (!std::isfinite(options.iso)) throw UsageError("isovalue: expected a finite number, got " + std::to_string(options.iso));
    if (!(options.error >= 0) || !std::isfinite(options.error)) {
        throw UsageError("error: expected a finite number >= 0, got " + std::to_string(options.error));
    }
    if (!(options.adaptivity >= 0 && options.adaptivity <= 1)) {
        throw UsageError("adaptivity: expected a number in [0, 1], got " + std::to_string(options.adaptivity));
    }
    if (options.open_boundary && options.method == MeshMethod::openvdb) {
        throw UsageError("open boundary: not available with the openvdb method (volumeToMesh meshes the grid's values as they are)");
    }
}

}  // namespace

Mesh mesh_grid(const openvdb::FloatGrid& grid, const MeshOptions& options) {
    check_options(options);
    switch (options.method) {
        case MeshMethod::dmc:
            return detail::dual_marching_cubes(grid, options);
        case MeshMethod::mc:
            return detail::marching_cubes(grid, options);
        case MeshMethod::openvdb:
            return detail::openvdb_volume_to_mesh(grid, options);
    }
    throw UsageError("mesh method: unknown value " + std::to_string(int(options.method)));
}

}  // namespace vdbmesh
