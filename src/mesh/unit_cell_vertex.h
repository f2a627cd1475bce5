#pragma once
// Private: the vertex of a unit cell of the dual mesh (contouring at --error 0 gives every
// simple unit cell one vertex; ifc_octree.cpp).

#include <array>

#include "mesh/edge_crossing.h"

namespace vdbmesh::detail {

/// How far a unit cell's vertex stays inside its cell (voxels): the face test between two cells'
/// vertices needs the segment strictly inside their face (kIfcInteriorMargin), and a vertex at
/// its cell's face makes slivers with the triangles over that face.
inline constexpr double kUnitVertexMargin = 0.05;

/// The vertex of a unit cell whose surface is one Marching Cubes sheet, in the cell's local
/// coordinates [0, 1]^3: the mean of its edge crossings @a mass_point (where volumeToMesh puts
/// its vertex at adaptivity 0), moved onto the isosurface of the trilinear interpolant of the
/// cell's @a corner_values (corner c at (c & 1, (c >> 1) & 1, c >> 2)) by Newton steps along the
/// gradient, then kept kUnitVertexMargin inside the cell. Where a value is not finite (beyond
/// the scan box) the mass point stays.
Point3d unit_cell_vertex(const std::array<double, 8>& corner_values, const Point3d& mass_point, double iso);

}  // namespace vdbmesh::detail
