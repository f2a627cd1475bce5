// Dual Marching Cubes on the VDB tree: the driver. Octrees per leaf (dmc_octree.cpp), dual
// cells (dmc_dual_cells.cpp), Marching Cubes on them (dmc_contour.cpp).

#include "mesh/dmc.h"

#include "mesh/dmc_contour.h"
#include "mesh/dmc_grid.h"
#include "mesh/dmc_octree.h"

namespace vdbmesh::detail {

Mesh dual_marching_cubes(const openvdb::FloatGrid& grid, const MeshOptions& options) {
    const DmcGrid dmc_grid = make_dmc_grid(grid, options);
    const std::vector<LeafOctree> octrees = build_leaf_octrees(dmc_grid, options.error);
    if (options.progress) options.progress(0.3);
    DmcContour contour = contour_dual_cells(dmc_grid, octrees, false, [&](double f) {
        if (options.progress) options.progress(0.3 + 0.7 * f);
    });
    return std::move(contour.mesh);
}

}  // namespace vdbmesh::detail
