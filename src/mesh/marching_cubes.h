#pragma once
// Private: Marching Cubes on a grid's samples (MeshMethod::mc).

#include <openvdb/openvdb.h>

#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::detail {

/// Marching Cubes on the samples of @a grid: a cell is 8 adjacent voxels, one vertex per grid
/// edge with a sign change (welded by edge) placed by edge_crossing.h, triangles from
/// mc_case(), counter-clockwise seen from outside in index space (mesh_grid() reverses
/// them when the transform mirrors space).
Mesh marching_cubes(const openvdb::FloatGrid& grid, const MeshOptions& options);

}  // namespace vdbmesh::detail
