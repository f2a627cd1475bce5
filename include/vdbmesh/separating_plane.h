#pragma once
// In vdbmesh::detail, shared by the geometry and processing stages (the exact triangle test and the
// decimator), not a stable API. Quick, conservative proofs that two triangles do not meet (or meet
// only at a shared corner), by a plane that separates them, decided in plain double arithmetic with
// a bound on its rounding. Any plane proves it, however it was chosen, so the plane is a guess
// (from the triangles' centroids); when the rounding leaves a doubt the answer is "not proven" and
// the exact test runs. triangles_intersect() on prepared triangles (below; the decimator's test)
// asks these first: most triangles the decimator tests are near but clearly apart, and the exact
// tests then go deep (nearly coplanar neighbours).

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "vdbmesh/geometry.h"

namespace vdbmesh::detail {

/// The value of axis . (p - origin) and a bound on its rounding error. The difference of the
/// coordinates and the three products and two sums each round once, so the error is below
/// 4 eps (1 + eps) times the sum of the terms' magnitudes; 8 eps leaves a margin.
struct SignedDistance {
    double value, error;
};
inline SignedDistance along(const Point3& axis, const Point3& origin, const Point3& p) {
    const double w0 = p[0] - origin[0], w1 = p[1] - origin[1], w2 = p[2] - origin[2];
    const double t0 = axis[0] * w0, t1 = axis[1] * w1, t2 = axis[2] * w2;
    constexpr double kBound = 8 * std::numeric_limits<double>::epsilon();
    return {t0 + t1 + t2, kBound * (std::fabs(t0) + std::fabs(t1) + std::fabs(t2))};
}

/// The plane of a triangle (a, b, c), for the signs of orient3d(a, b, c, d) at many points d
/// when the plain double evaluation certainly has them, else 0 (unknown): the exact predicate's
/// own filter, a margin over J. R. Shewchuk's bound (7 + 56 eps) eps times the permanent, with
/// the triangle's part of the products computed once.
class CertainPlane {
public:
    CertainPlane(const Point3& a, const Point3& b, const Point3& c) : a_(a) {
        const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
        const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
        m_ = {uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx};
        p_ = {std::fabs(uy * vz) + std::fabs(uz * vy), std::fabs(uz * vx) + std::fabs(ux * vz), std::fabs(ux * vy) + std::fabs(uy * vx)};
    }

    int side(const Point3& d) const {
        const double wx = d[0] - a_[0], wy = d[1] - a_[1], wz = d[2] - a_[2];
        const double det = wx * m_[0] + wy * m_[1] + wz * m_[2];
        const double permanent = std::fabs(wx) * p_[0] + std::fabs(wy) * p_[1] + std::fabs(wz) * p_[2];
        constexpr double kBound = 1e-15;
        return det > kBound * permanent ? 1 : det < -kBound * permanent ? -1 : 0;
    }

private:
    Point3 a_, m_, p_;
};

inline Point3 centroid(const Triangle3& t) {
    return {(t[0][0] + t[1][0] + t[2][0]) / 3, (t[0][1] + t[1][1] + t[2][1]) / 3, (t[0][2] + t[1][2] + t[2][2]) / 3};
}

/// A triangle with what the proofs below read of it beside its corners (centroid, plane),
/// computed once for the many pairs it takes part in.
struct PreparedTriangle {
    explicit PreparedTriangle(const Triangle3& t) : corners(t), centroid(detail::centroid(t)), plane(t[0], t[1], t[2]) {}
    Triangle3 corners;
    Point3 centroid;
    CertainPlane plane;
};

/// True when all of @a u lies certainly strictly on one side of t's plane, or all of t on one
/// side of u's (then the triangles share no point).
inline bool certainly_apart_by_plane(const PreparedTriangle& t, const PreparedTriangle& u) {
    for (int pass = 0; pass < 2; ++pass) {
        const PreparedTriangle& a = pass == 0 ? t : u;
        const Triangle3& b = (pass == 0 ? u : t).corners;
        const int side = a.plane.side(b[0]);
        if (side != 0 && a.plane.side(b[1]) == side && a.plane.side(b[2]) == side) return true;
    }
    return false;
}

/// True when the triangles t and u, sharing the corner t[k] = u[j], certainly meet only there
/// because u's other corners lie strictly on the same side of t's plane, or t's other corners
/// on the same side of u's plane.
inline bool certainly_apart_of_plane(const PreparedTriangle& t, int k, const PreparedTriangle& u, int j) {
    const int s1 = t.plane.side(u.corners[(j + 1) % 3]);
    if (s1 != 0 && s1 == t.plane.side(u.corners[(j + 2) % 3])) return true;
    const int s2 = u.plane.side(t.corners[(k + 1) % 3]);
    return s2 != 0 && s2 == u.plane.side(t.corners[(k + 2) % 3]);
}

/// True when a plane certainly has all of @a t strictly on one side and all of @a u strictly
/// on the other (then the closed triangles share no point). The plane is across the line
/// between the centroids.
inline bool certainly_apart(const PreparedTriangle& t, const PreparedTriangle& u) {
    const Point3& origin = t.centroid;
    const Point3 axis{u.centroid[0] - origin[0], u.centroid[1] - origin[1], u.centroid[2] - origin[2]};
    double t_high = -std::numeric_limits<double>::infinity(), u_low = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const SignedDistance a = along(axis, origin, t.corners[k]), b = along(axis, origin, u.corners[k]);
        t_high = std::max(t_high, a.value + a.error);
        u_low = std::min(u_low, b.value - b.error);
    }
    return t_high < u_low;
}

/// True when the triangles t and (corner, u1, u2), sharing @a corner = t[k], certainly meet only
/// there: a plane through the corner has t's two other corners strictly on one side and u1, u2
/// strictly on the other (every other point of a triangle is a convex combination giving weight
/// to a far corner). The plane is across the difference of the directions from the corner to
/// the middles of the far edges.
inline bool certainly_meet_only_at(const Triangle3& t, int k, const Point3& u1, const Point3& u2) {
    const Point3& corner = t[k];
    const Point3& t1 = t[k == 2 ? 0 : k + 1];
    const Point3& t2 = t[k == 0 ? 2 : k - 1];
    Point3 to_t, to_u;
    for (int i = 0; i < 3; ++i) to_t[i] = t1[i] + t2[i] - 2 * corner[i], to_u[i] = u1[i] + u2[i] - 2 * corner[i];
    // |to_u| to_t - |to_t| to_u: the difference of the unit directions, scaled.
    const double t_length = std::sqrt(to_t[0] * to_t[0] + to_t[1] * to_t[1] + to_t[2] * to_t[2]);
    const double u_length = std::sqrt(to_u[0] * to_u[0] + to_u[1] * to_u[1] + to_u[2] * to_u[2]);
    const Point3 axis{to_t[0] * u_length - to_u[0] * t_length, to_t[1] * u_length - to_u[1] * t_length,
                      to_t[2] * u_length - to_u[2] * t_length};
    const SignedDistance a = along(axis, corner, t1), b = along(axis, corner, t2);
    const SignedDistance c = along(axis, corner, u1), d = along(axis, corner, u2);
    return a.value > a.error && b.value > b.error && -c.value > c.error && -d.value > d.error;
}

/// True when the triangles (s0, s1, p) and (s1, s0, q), sharing the edge s0 s1, certainly meet
/// only on it: p and q lie strictly on either side (exact orientations) of a plane through the
/// edge, the one through a point off t's plane along its normal (then every other point of
/// each triangle does, being a convex combination giving weight to p, or to q).
inline bool certainly_meet_only_on_edge(const Point3& s0, const Point3& s1, const Point3& p, const Point3& q) {
    const Point3 e{s1[0] - s0[0], s1[1] - s0[1], s1[2] - s0[2]}, f{p[0] - s0[0], p[1] - s0[1], p[2] - s0[2]};
    const Point3 off{s0[0] + e[1] * f[2] - e[2] * f[1], s0[1] + e[2] * f[0] - e[0] * f[2], s0[2] + e[0] * f[1] - e[1] * f[0]};
    const CertainPlane plane(s0, s1, off);
    const int p_certain = plane.side(p);
    if (p_certain != 0 && plane.side(q) == -p_certain) return true;
    const int p_side = orient3d(s0, s1, off, p);
    return p_side != 0 && orient3d(s0, s1, off, q) == -p_side;
}

/// triangles_intersect() (vdbmesh/geometry.h) on prepared triangles: the same answer, the proof
/// above for how the triangles share corners tried before the exact test.
bool triangles_intersect(const std::array<std::uint32_t, 3>& t_ids, const PreparedTriangle& t,
                         const std::array<std::uint32_t, 3>& u_ids, const PreparedTriangle& u);

/// Whether that proof alone settles that the triangles do not meet beyond what they share.
bool proven_apart(const std::array<std::uint32_t, 3>& t_ids, const PreparedTriangle& t, const std::array<std::uint32_t, 3>& u_ids,
                  const PreparedTriangle& u);

}  // namespace vdbmesh::detail
