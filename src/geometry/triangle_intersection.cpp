// Exact tests between closed triangles, built only from the signs of orientation
// determinants (exact_predicates.h), so they never misjudge a touching or coplanar case.
// - Two non-coplanar triangles meet iff an edge of one meets the other: their intersection is
//   a segment of the planes' common line whose ends lie on the boundary of one triangle.
// - A segment crossing a triangle's plane meets the triangle iff its line passes inside the
//   three edges (the signs of orient3d(a, b, edge) agree: the Plücker-coordinate test).
// - Coplanar cases are decided in the projection along an axis the plane is not parallel to,
//   an affine bijection that keeps every incidence.
#include "geometry/triangle_intersection.h"

#include <algorithm>

namespace vdbmesh::detail {
namespace {

/// The coordinate axis to drop so that triangle t projects to a non-degenerate triangle.
int projection_axis(const Triangle3& t) {
    for (int axis = 0; axis < 3; ++axis) {
        const int i = (axis + 1) % 3, j = (axis + 2) % 3;
        if (orient2d({t[0][i], t[0][j]}, {t[1][i], t[1][j]}, {t[2][i], t[2][j]}) != 0) return axis;
    }
    return 2;  // only for degenerate triangles, which callers exclude
}

Point2 project(const Point3& p, int axis) { return {p[(axis + 1) % 3], p[(axis + 2) % 3]}; }

/// p lies within the bounding box of the collinear segment [a, b].
bool within_box(const Point2& p, const Point2& a, const Point2& b) {
    for (int k = 0; k < 2; ++k) {
        if (p[k] < std::min(a[k], b[k]) || p[k] > std::max(a[k], b[k])) return false;
    }
    return true;
}

/// Closed segments [a, b] and [c, d] in the plane share a point.
bool segments_meet_2d(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
    const int abc = orient2d(a, b, c), abd = orient2d(a, b, d);
    const int cda = orient2d(c, d, a), cdb = orient2d(c, d, b);
    if (abc * abd < 0 && cda * cdb < 0) return true;
    if (abc == 0 && within_box(c, a, b)) return true;
    if (abd == 0 && within_box(d, a, b)) return true;
    if (cda == 0 && within_box(a, c, d)) return true;
    if (cdb == 0 && within_box(b, c, d)) return true;
    return false;
}

/// p lies in the closed non-degenerate triangle t.
bool point_in_triangle_2d(const Point2& p, const std::array<Point2, 3>& t) {
    const int s0 = orient2d(t[0], t[1], p), s1 = orient2d(t[1], t[2], p), s2 = orient2d(t[2], t[0], p);
    const bool has_negative = s0 < 0 || s1 < 0 || s2 < 0;
    const bool has_positive = s0 > 0 || s1 > 0 || s2 > 0;
    return !(has_negative && has_positive);
}

std::array<Point2, 3> project(const Triangle3& t, int axis) {
    return {project(t[0], axis), project(t[1], axis), project(t[2], axis)};
}

bool segment_meets_triangle_2d(const Point2& a, const Point2& b, const std::array<Point2, 3>& t) {
    if (point_in_triangle_2d(a, t) || point_in_triangle_2d(b, t)) return true;
    for (int k = 0; k < 3; ++k) {
        if (segments_meet_2d(a, b, t[k], t[(k + 1) % 3])) return true;
    }
    return false;
}

bool coplanar_triangles_meet(const Triangle3& t, const Triangle3& u) {
    const int axis = projection_axis(t);
    const std::array<Point2, 3> t2 = project(t, axis), u2 = project(u, axis);
    for (int k = 0; k < 3; ++k) {
        if (segment_meets_triangle_2d(u2[k], u2[(k + 1) % 3], t2)) return true;
    }
    // Either u has a point in t (an edge of u meets t), or u contains t entirely.
    return point_in_triangle_2d(t2[0], u2);
}

/// The closed ray from s through x lies in the wedge at s spanned counter-clockwise from a to b
/// (an angle below 180 degrees).
bool ray_in_wedge(const Point2& s, const Point2& a, const Point2& b, const Point2& x) {
    return orient2d(s, a, x) >= 0 && orient2d(s, b, x) <= 0;
}

/// Coplanar triangles sharing the corner t[0] == u[0] share more than it iff their wedges at
/// that corner do: two convex wedges overlap iff one holds a boundary ray of the other.
bool coplanar_wedges_overlap(const Triangle3& t, const Triangle3& u) {
    const int axis = projection_axis(t);
    std::array<Point2, 3> t2 = project(t, axis), u2 = project(u, axis);
    if (orient2d(t2[0], t2[1], t2[2]) < 0) std::swap(t2[1], t2[2]);
    if (orient2d(u2[0], u2[1], u2[2]) < 0) std::swap(u2[1], u2[2]);
    const Point2& s = t2[0];
    return ray_in_wedge(s, t2[1], t2[2], u2[1]) || ray_in_wedge(s, t2[1], t2[2], u2[2]) ||
           ray_in_wedge(s, u2[1], u2[2], t2[1]) || ray_in_wedge(s, u2[1], u2[2], t2[2]);
}

/// All three signs are >= 0 or all are <= 0.
bool signs_agree(int s0, int s1, int s2) {
    return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

}  // namespace

bool segment_meets_triangle(const Point3& a, const Point3& b, const Triangle3& t) {
    const int sa = orient3d(t[0], t[1], t[2], a), sb = orient3d(t[0], t[1], t[2], b);
    if (sa * sb > 0) return false;
    if (sa == 0 && sb == 0) {
        const int axis = projection_axis(t);
        return segment_meets_triangle_2d(project(a, axis), project(b, axis), project(t, axis));
    }
    // The line ab crosses the plane at one point (a or b itself when it lies on the plane):
    // it is inside the closed triangle when it passes on the same side of all three edges.
    return signs_agree(orient3d(a, b, t[0], t[1]), orient3d(a, b, t[1], t[2]), orient3d(a, b, t[2], t[0]));
}

bool triangles_meet(const Triangle3& t, const Triangle3& u) {
    const int t0 = orient3d(u[0], u[1], u[2], t[0]), t1 = orient3d(u[0], u[1], u[2], t[1]),
              t2 = orient3d(u[0], u[1], u[2], t[2]);
    if ((t0 > 0 && t1 > 0 && t2 > 0) || (t0 < 0 && t1 < 0 && t2 < 0)) return false;
    if (t0 == 0 && t1 == 0 && t2 == 0) return coplanar_triangles_meet(t, u);
    const int u0 = orient3d(t[0], t[1], t[2], u[0]), u1 = orient3d(t[0], t[1], t[2], u[1]),
              u2 = orient3d(t[0], t[1], t[2], u[2]);
    if ((u0 > 0 && u1 > 0 && u2 > 0) || (u0 < 0 && u1 < 0 && u2 < 0)) return false;
    for (int k = 0; k < 3; ++k) {
        if (segment_meets_triangle(t[k], t[(k + 1) % 3], u)) return true;
        if (segment_meets_triangle(u[k], u[(k + 1) % 3], t)) return true;
    }
    return false;
}

bool triangles_meet_beyond_corner(const Triangle3& t, const Triangle3& u) {
    // Non-coplanar: the intersection lies on the planes' common line through the corner, so if
    // the far edge of either triangle is strictly on one side of the other's plane, the
    // triangles meet only at the corner.
    const int t1 = orient3d(u[0], u[1], u[2], t[1]), t2 = orient3d(u[0], u[1], u[2], t[2]);
    if (t1 == 0 && t2 == 0) return coplanar_wedges_overlap(t, u);
    if (t1 * t2 > 0) return false;
    const int u1 = orient3d(t[0], t[1], t[2], u[1]), u2 = orient3d(t[0], t[1], t[2], u[2]);
    if (u1 * u2 > 0) return false;
    // Otherwise the intersection is convex and contains the shared corner; if it holds another
    // point it reaches the edge of t or of u opposite that corner (which does not contain it).
    return segment_meets_triangle(t[1], t[2], u) || segment_meets_triangle(u[1], u[2], t);
}

bool triangles_meet_beyond_edge(const Point3& s0, const Point3& s1, const Point3& p, const Point3& q) {
    if (orient3d(s0, s1, p, q) != 0) return false;
    const int axis = projection_axis({s0, s1, p});
    const Point2 a = project(s0, axis), b = project(s1, axis);
    return orient2d(a, b, project(p, axis)) == orient2d(a, b, project(q, axis));
}

}  // namespace vdbmesh::detail
