#pragma once
// The page's close-up triangles: the full mesh's triangles near a box, made by meshing only the
// nodes round the box from a grid read by region (never the whole grid or the whole mesh).

#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::view {

/// The triangles of the full mesh of @a source (mesh_grid() of the whole grid at @a options)
/// with at least one corner inside @a box (index space, min inclusive, max exclusive), in the
/// full mesh's order, with only the vertices they use. Reads and meshes the box's nodes and
/// the nodes one below and two above them (docs/dmc.md, "Bricks": what decides a triangle).
Mesh region_mesh(const GridRegionSource& source, const IndexBox& box, const MeshOptions& options);

}  // namespace vdbmesh::view
