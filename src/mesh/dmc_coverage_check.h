#pragma once
// Private: the other direction of Dual Marching Cubes' self-check. dmc_self_check.h judges
// the triangles against the isosurface; here the isosurface is judged against the mesh: every
// crossing of the isosurface with a grid edge inside a merged cell (a vertex of the Marching
// Cubes mesh, on the trilinear isosurface) must lie within the tolerance of the mesh. Where
// one does not, the merge lost surface (a bump flattened, a thin part cut off, a tunnel
// closed) and the cell must be split.

#include <vector>

#include "mesh/dmc_contour.h"
#include "mesh/dmc_grid.h"
#include "mesh/dmc_octree.h"
#include "mesh/dmc_self_check.h"

namespace vdbmesh::detail {

/// A voxel of each merged cell of @a octrees holding a crossing farther than @a tolerance
/// voxels from the mesh of @a contour (made from @a octrees), and of the merged cells next to
/// a voxel holding one, in leaf order. Without @a since every leaf is judged; with it (the
/// cells split since the last call), only leaves next to a leaf it changed: the mesh changed
/// only there.
std::vector<LeafVoxel> cells_missing_surface(const DmcGrid& grid, const std::vector<LeafOctree>& octrees,
                                             const DmcContour& contour, double tolerance, const SplitVoxels* since);

}  // namespace vdbmesh::detail
