#pragma once
// Private: intersection-free octree contouring (MeshMethod::dc).

#include <openvdb/openvdb.h>

#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::detail {

/// Dual Contouring on the octree of every 8^3 leaf with Marching Cubes in the unit cells that
/// keep no vertex
/// (ifc_octree.cpp merges, ifc_polygons.cpp triangulates), closed, manifold and free of
/// self-intersections by construction, at any options.error (0: the dual mesh, a vertex per
/// simple unit cell, ifc_octree.cpp and unit_cell_vertex.h). Adds its
/// phases ("octree", "contour", "weld") to @a report.
Mesh intersection_free_contouring(const openvdb::FloatGrid& grid, const MeshOptions& options, MeshReport& report);

}  // namespace vdbmesh::detail
