#pragma once
// Private: exact orientation predicates on double coordinates (adaptive: a floating-point
// filter, then exact expansion arithmetic when the filter cannot decide).

#include <array>

#include "vdbmesh/geometry.h"

namespace vdbmesh::detail {

using Point2 = std::array<double, 2>;

/// Exact sign (-1, 0, +1) of ((b - a) x (c - a)) . (d - a): positive when d lies on the side
/// the normal of the counter-clockwise triangle abc points to, 0 when the four are coplanar.
int orient3d(const Point3& a, const Point3& b, const Point3& c, const Point3& d);

/// Exact sign of (b - a) x (c - a): positive when abc turns counter-clockwise.
int orient2d(const Point2& a, const Point2& b, const Point2& c);

/// True when the three points are exactly collinear (or coincide).
bool collinear(const Point3& a, const Point3& b, const Point3& c);

}  // namespace vdbmesh::detail
