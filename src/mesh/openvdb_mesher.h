#pragma once
// Private: OpenVDB's own mesher (MeshMethod::openvdb), for comparison.

#include <openvdb/openvdb.h>

#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::detail {

/// openvdb::tools::volumeToMesh at options.iso and options.adaptivity, quads split along their
/// shorter diagonal, triangles wound counter-clockwise seen from outside the object in index
/// space (mesh_grid() reverses them when the transform mirrors space). The grid's
/// values are used as they are: no scan-box closing, options.open_boundary ignored (see the .cpp).
Mesh openvdb_volume_to_mesh(const openvdb::FloatGrid& grid, const MeshOptions& options);

}  // namespace vdbmesh::detail
