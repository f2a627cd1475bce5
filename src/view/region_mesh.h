#pragma once
// The page's close-up triangles: the full mesh's triangles near a box, made by meshing only the
// nodes round the box from a grid read by region (never the whole grid or the whole mesh).

#include <cstdint>

#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::view {

/// What region_mesh() of @a box reads: the box's nodes and the nodes one below and two above
/// them, with the two leaves of sample windows round them.
IndexBox region_read_box(const IndexBox& box);

/// The triangles of the full mesh of @a source (mesh_grid() of the whole grid at @a options)
/// with at least one corner inside @a box (index space, min inclusive, max exclusive), in the
/// full mesh's order, with only the vertices they use. Reads and meshes the box's nodes and
/// the nodes one below and two above them (docs/dmc.md, "Bricks": what decides a triangle).
/// @throw UsageError naming the box when that read would hold more than @a max_read_bytes
/// (GridRegionSource::estimated_bytes()), before reading anything.
Mesh region_mesh(const GridRegionSource& source, const IndexBox& box, const MeshOptions& options, std::uint64_t max_read_bytes);

}  // namespace vdbmesh::view
