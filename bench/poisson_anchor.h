#pragma once
// CGAL's Poisson surface reconstruction, the anchor of vdbmesh_points_bench (CGAL kept out of
// the other translation units).

#include "vdbmesh/mesh.h"
#include "vdbmesh/points.h"

namespace vdbmesh::bench {

/// Points with oriented normals to a mesh by CGAL::poisson_surface_reconstruction_delaunay
/// (the spacing is the average 6-neighbour spacing times @a spacing_scale).
Mesh cgal_poisson(const PointCloud& cloud, double spacing_scale = 1.0);

}  // namespace vdbmesh::bench
