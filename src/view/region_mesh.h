#pragma once
// The page's close-up triangles: the full mesh's triangles near a box, made by meshing only the
// nodes round the box from a grid read by region (never the whole grid or the whole mesh).

#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::view {

/// The triangles of the full mesh of @a source (mesh_grid() of the whole grid at @a options)
/// with at least one corner inside @a box (index space, min inclusive, max exclusive), in the
/// full mesh's order, with only the vertices they use. Meshes the nodes within one node of
/// the box, by bricks of one node for DC at an error > 0 (docs/dmc.md, "Bricks": the same
/// triangles as the whole run), else as one region (the meshers' cells read one voxel away).
Mesh region_mesh(const GridRegionSource& source, const IndexBox& box, const MeshOptions& options);

}  // namespace vdbmesh::view
