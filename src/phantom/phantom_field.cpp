// Exact Euclidean signed distance functions of the phantom shapes, in the shape's own frame
// (centred at the origin, unrotated). Table 3.1 of the DMC coursework (000_*.txt) composes
// blurred indicator functions instead, e.g. the cylinder as s(sqrt(x^2 + y^2) - 40, 5) *
// s(|z| - 60, 0); the 0.5 level of such a product is not the shape near its edges, so here
// each shape has one exact distance and the blur is applied once to it (phantom.cpp).
//
// The cube minus a ball needs care: max(box, -ball) is exact inside the solid but only a lower
// bound outside it. There the distance is the minimum over the pieces of the surface: the six
// faces with a disc removed, and the part of the sphere inside the cube (see
// cube_minus_ball_distance).

#include "phantom_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vdbmesh::detail {

namespace {

using Vec3 = std::array<double, 3>;
constexpr double kPi = 3.14159265358979323846;

double norm(const Vec3& p) { return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]); }

/// Signed distance to the axis-aligned cube [-h, h]^3.
double box_distance(const Vec3& p, double h) {
    const Vec3 q{std::abs(p[0]) - h, std::abs(p[1]) - h, std::abs(p[2]) - h};
    const double outside = norm({std::max(q[0], 0.0), std::max(q[1], 0.0), std::max(q[2], 0.0)});
    const double inside = std::min(std::max({q[0], q[1], q[2]}), 0.0);
    return outside + inside;
}

/// Signed distance to the cylinder of radius r about the z axis, |z| <= half_height.
double cylinder_distance(const Vec3& p, double r, double half_height) {
    const double radial = std::hypot(p[0], p[1]) - r;
    const double axial = std::abs(p[2]) - half_height;
    const double outside = std::hypot(std::max(radial, 0.0), std::max(axial, 0.0));
    return outside + std::min(std::max(radial, axial), 0.0);
}

/// Signed distance to the ring torus in the xy-plane: distance to its core circle minus the tube radius.
double torus_distance(const Vec3& p, double major, double minor) {
    return std::hypot(std::hypot(p[0], p[1]) - major, p[2]) - minor;
}

/// The surface of the cube [-h, h]^3 minus the open ball of radius rs (both centred at the
/// origin, rs < h * sqrt(2)) is made of
///  - on each face, the square minus the disc u^2 + v^2 < rho^2, rho^2 = rs^2 - h^2 (no disc
///    when rho^2 <= 0); the disc lies strictly inside the square since rho < h;
///  - the part of the sphere inside the cube: all of it when rs <= h, else the sphere minus six
///    disjoint caps, bounded by the six circles of radius rho on the faces.
/// The distance to a region of a plane or sphere is reached at the foot of the perpendicular
/// when that foot is in the region, else on the region's boundary (distance to the foot grows
/// monotonically away from it). Returns the unsigned distance to that surface.
double cube_minus_ball_distance(const Vec3& p, double h, double rs) {
    const double rho2 = rs * rs - h * h;
    const double rho = rho2 > 0 ? std::sqrt(rho2) : 0.0;
    double best = std::numeric_limits<double>::infinity();

    // Faces: (axis n, side sign) with in-plane coordinates (u, v).
    for (int n = 0; n < 3; ++n) {
        const double u = p[(n + 1) % 3], v = p[(n + 2) % 3];
        const double in_plane_radius = std::hypot(u, v);
        double in_plane = 0;  // distance within the plane from (u, v) to the face region
        if (std::abs(u) <= h && std::abs(v) <= h) {
            if (rho2 > 0 && in_plane_radius < rho) in_plane = rho - in_plane_radius;
        } else {
            in_plane = std::hypot(u - std::clamp(u, -h, h), v - std::clamp(v, -h, h));
        }
        for (double side : {-1.0, 1.0}) {
            const double normal = p[n] - side * h;
            best = std::min(best, std::hypot(normal, in_plane));
            // The circle bounding this face's disc, also the boundary of the sphere patch.
            if (rho2 > 0) best = std::min(best, std::hypot(normal, in_plane_radius - rho));
        }
    }

    // The sphere patch: its nearest point is the radial projection when that lies in the cube;
    // otherwise it is on a bounding circle, already counted above.
    const double r = norm(p);
    if (r == 0) return std::min(best, rs);
    const double k = rs / r;
    if (std::max({std::abs(p[0] * k), std::abs(p[1] * k), std::abs(p[2] * k)}) <= h)
        best = std::min(best, std::abs(r - rs));
    return best;
}

/// Signed distance to the cube [-h, h]^3 minus the open ball of radius rs.
double cube_minus_ball_signed_distance(const Vec3& p, double h, double rs) {
    const double box = box_distance(p, h);
    const double ball = norm(p) - rs;
    // Inside the solid the nearest outside point is outside the cube or inside the ball:
    // the distance to a union is the minimum of the distances.
    if (box < 0 && ball > 0) return std::max(box, -ball);
    return cube_minus_ball_distance(p, h, rs);
}

/// Rz(gamma) * Ry(beta) * Rx(alpha), angles in degrees.
std::array<Vec3, 3> rotation_matrix(const std::array<double, 3>& degrees) {
    const double a = degrees[0] * kPi / 180, b = degrees[1] * kPi / 180, c = degrees[2] * kPi / 180;
    const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b), cc = std::cos(c),
                 sc = std::sin(c);
    return {{{cc * cb, cc * sb * sa - sc * ca, cc * sb * ca + sc * sa},
             {sc * cb, sc * sb * sa + cc * ca, sc * sb * ca - cc * sa},
             {-sb, cb * sa, cb * ca}}};
}

}  // namespace

PhantomField::PhantomField(const PhantomSpec& spec)
    : spec_(spec), centre_(spec.centre_or_default()), rotation_(rotation_matrix(spec.rotation_degrees)) {
    validate_phantom(spec);
}

double PhantomField::signed_distance(double x, double y, double z) const {
    const Vec3 d{x - centre_[0], y - centre_[1], z - centre_[2]};
    Vec3 p{};  // R^T d: the point in the shape's frame
    for (int i = 0; i < 3; ++i) p[i] = rotation_[0][i] * d[0] + rotation_[1][i] * d[1] + rotation_[2][i] * d[2];
    switch (spec_.shape) {
        case PhantomShape::sphere: return norm(p) - spec_.radius;
        case PhantomShape::cube: return box_distance(p, spec_.side / 2);
        case PhantomShape::cylinder: return cylinder_distance(p, spec_.radius, spec_.height / 2);
        case PhantomShape::cube_minus_sphere: return cube_minus_ball_signed_distance(p, spec_.side / 2, spec_.hole_radius);
        case PhantomShape::torus: return torus_distance(p, spec_.radius, spec_.tube_radius);
    }
    return 0;
}

std::array<double, 3> PhantomField::to_volume(const Vec3& p) const {
    Vec3 v{};
    for (int i = 0; i < 3; ++i) v[i] = centre_[i] + rotation_[i][0] * p[0] + rotation_[i][1] * p[1] + rotation_[i][2] * p[2];
    return v;
}

double PhantomField::density(double x, double y, double z) const {
    return phantom_blur(signed_distance(x, y, z), spec_.blur);
}

}  // namespace vdbmesh::detail
