#pragma once
// Whether two meshes hold the same triangles (as corner positions, orientation kept),
// whatever the order of their vertices and triangles: Dual Marching Cubes at error 0 and
// Marching Cubes number them differently but must make the same surface.

#include "vdbmesh/mesh.h"

namespace vdbmesh::test {

bool same_triangles(const Mesh& a, const Mesh& b);

}  // namespace vdbmesh::test
