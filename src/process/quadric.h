#pragma once
// Private: the error quadric of Garland and Heckbert (SIGGRAPH 1997): the sum of squared
// distances to a set of planes, as a symmetric 4x4 matrix (10 coefficients).

#include <array>
#include <cmath>
#include <optional>

namespace vdbmesh::detail {

using Vec3d = std::array<double, 3>;

struct Quadric {
    // | a2 ab ac ad |
    // |    b2 bc bd |
    // |       c2 cd |
    // |          d2 |
    double a2 = 0, ab = 0, ac = 0, ad = 0, b2 = 0, bc = 0, bd = 0, c2 = 0, cd = 0, d2 = 0;

    /// The plane through @a point with unit normal @a n.
    static Quadric plane(const Vec3d& n, const Vec3d& point) {
        const double d = -(n[0] * point[0] + n[1] * point[1] + n[2] * point[2]);
        return {n[0] * n[0], n[0] * n[1], n[0] * n[2], n[0] * d, n[1] * n[1], n[1] * n[2], n[1] * d, n[2] * n[2], n[2] * d, d * d};
    }

    Quadric operator+(const Quadric& o) const {
        return {a2 + o.a2, ab + o.ab, ac + o.ac, ad + o.ad, b2 + o.b2, bc + o.bc, bd + o.bd, c2 + o.c2, cd + o.cd, d2 + o.d2};
    }

    /// The sum of squared distances of @a p to the planes (clamped at 0 against rounding).
    double error(const Vec3d& p) const {
        const double x = p[0], y = p[1], z = p[2];
        const double e = a2 * x * x + 2 * ab * x * y + 2 * ac * x * z + 2 * ad * x + b2 * y * y + 2 * bc * y * z + 2 * bd * y +
                         c2 * z * z + 2 * cd * z + d2;
        return e > 0 ? e : 0;
    }

    /// The point of least error, when the 3x3 system is well conditioned relative to its size.
    std::optional<Vec3d> minimizer() const {
        const double det = a2 * (b2 * c2 - bc * bc) - ab * (ab * c2 - bc * ac) + ac * (ab * bc - b2 * ac);
        const double scale = a2 + b2 + c2;
        if (!(std::abs(det) > 1e-6 * scale * scale * scale)) return std::nullopt;
        // Cramer's rule on A p = -(ad, bd, cd).
        const double r0 = -ad, r1 = -bd, r2 = -cd;
        const double x = (r0 * (b2 * c2 - bc * bc) - ab * (r1 * c2 - bc * r2) + ac * (r1 * bc - b2 * r2)) / det;
        const double y = (a2 * (r1 * c2 - bc * r2) - r0 * (ab * c2 - bc * ac) + ac * (ab * r2 - r1 * ac)) / det;
        const double z = (a2 * (b2 * r2 - r1 * bc) - ab * (ab * r2 - r1 * ac) + r0 * (ab * bc - b2 * ac)) / det;
        return Vec3d{x, y, z};
    }
};

}  // namespace vdbmesh::detail
