#pragma once
// Private: the dual surface (MeshMethod::dual, experimental; docs/dmc.md, "Error 0: the dual
// mesh"): a vertex per Marching Cubes polygon of each cell, on the cell's trilinear
// isosurface, a quad per crossed grid edge, and a proof that no two triangles cross.

#include <openvdb/openvdb.h>

#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::detail {

struct DualProofFigures;

/// The dual surface of @a grid at options.iso, triangles counter-clockwise seen from outside in
/// index space (mesh_grid() reverses them when the transform mirrors space). Its phases
/// ("vertices", "proof", "fallback", "triangles") go to @a report, with the vertices the proof
/// moved back to their crossings' means; what the proof did to @a figures when given. The same
/// bytes for any thread count.
Mesh dual_surface(const openvdb::FloatGrid& grid, const MeshOptions& options, MeshReport& report, DualProofFigures* figures = nullptr);

}  // namespace vdbmesh::detail
