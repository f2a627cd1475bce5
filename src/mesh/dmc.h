#pragma once
// Private: Dual Marching Cubes on the VDB tree (MeshMethod::dmc, the default mesher).

#include <openvdb/openvdb.h>

#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::detail {

/// Dual Marching Cubes (Schaefer and Warren 2004) on the depth-3 octree of every 8^3 leaf,
/// cells merged while their 4D QEF error stays under options.error voxels (0: every voxel is
/// a cell, and the mesh equals Marching Cubes on the samples). See mesh_grid().
/// Adds its phases ("octree", "contour", "check") to @a report, with the safety-net rounds
/// run and, when they ran out, the Marching Cubes fallback.
Mesh dual_marching_cubes(const openvdb::FloatGrid& grid, const MeshOptions& options, MeshReport& report);
/// The same without a report.
Mesh dual_marching_cubes(const openvdb::FloatGrid& grid, const MeshOptions& options);

}  // namespace vdbmesh::detail
