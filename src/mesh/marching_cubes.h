#pragma once
// Private: Marching Cubes on a grid's samples (MeshMethod::mc).

#include <openvdb/openvdb.h>

#include <vector>

#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::detail {

/// Marching Cubes on the samples of @a grid: a cell is 8 adjacent voxels, one vertex per grid
/// edge with a sign change (welded by edge) placed by edge_crossing.h, triangles from
/// mc_case(), counter-clockwise seen from outside in index space (mesh_grid() reverses
/// them when the transform mirrors space).
Mesh marching_cubes(const openvdb::FloatGrid& grid, const MeshOptions& options);

class SampleClassifier;
struct IfcNodeOutput;

/// The same mesh's part made by the blocks whose origins lie in @a blocks_within (whole nodes:
/// a brick, docs/dmc.md "Bricks"), with @a grid holding the samples they read (one voxel
/// beyond), as DC's nodes are: vertices and triangle corners named by their grid edges' keys
/// (ifc_edge_key()), so that DC's spill welds them. Welded node by node in z-major order, the
/// parts of every brick give marching_cubes()'s bytes.
std::vector<IfcNodeOutput> marching_cubes_nodes(const openvdb::FloatGrid& grid, const SampleClassifier& classifier, const MeshOptions& options,
                                                const openvdb::CoordBBox& blocks_within);

}  // namespace vdbmesh::detail
