#pragma once
// Private: exact intersection tests between closed triangles and segments in 3D.

#include <array>

#include "geometry/exact_predicates.h"

namespace vdbmesh::detail {

using Triangle3 = std::array<Point3, 3>;

/// True when the closed segment [a, b] and the closed non-degenerate triangle t share a point.
bool segment_meets_triangle(const Point3& a, const Point3& b, const Triangle3& t);

/// True when two closed non-degenerate triangles share a point.
bool triangles_meet(const Triangle3& t, const Triangle3& u);

/// Two non-degenerate triangles sharing exactly the corner t[0] == u[0]: true when they also
/// share another point (a fold onto each other or a crossing).
bool triangles_meet_beyond_corner(const Triangle3& t, const Triangle3& u);

/// Two non-degenerate triangles sharing exactly the edge (s0, s1); p and q are their third
/// corners: true when they overlap (coplanar, p and q on the same side of the edge).
bool triangles_meet_beyond_edge(const Point3& s0, const Point3& s1, const Point3& p, const Point3& q);

}  // namespace vdbmesh::detail
