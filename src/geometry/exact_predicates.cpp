// Exact orientation predicates after J. R. Shewchuk, "Adaptive Precision Floating-Point
// Arithmetic and Fast Robust Geometric Predicates", Discrete Comput. Geom. 18 (1997) 305-363:
// a floating-point evaluation whose error bound decides almost every call, and otherwise the
// exact value as a nonoverlapping expansion (a sum of doubles) whose sign is that of its
// largest component. Differences are kept exact (two-term expansions), so the result is exact
// for any finite double input. Needs IEEE round-to-nearest doubles without extended precision
// (x86-64 SSE) and no contraction into fused multiply-adds (ISO C++ mode).
#include "geometry/exact_predicates.h"

#include <algorithm>
#include <cmath>

namespace vdbmesh::detail {
namespace {

// Relative error bounds of the plain floating-point determinants, with margin over
// Shewchuk's (3 + 16 eps) eps and (7 + 56 eps) eps.
constexpr double kOrient2dBound = 4e-16;
constexpr double kOrient3dBound = 1e-15;

/// a + b = x + y exactly (Knuth's TwoSum).
inline void two_sum(double a, double b, double& x, double& y) {
    x = a + b;
    const double b_virtual = x - a;
    const double a_virtual = x - b_virtual;
    y = (a - a_virtual) + (b - b_virtual);
}

/// Dekker's split of a into two halves of 26 bits each.
inline void split(double a, double& high, double& low) {
    const double c = 134217729.0 * a;  // 2^27 + 1
    high = c - (c - a);
    low = a - high;
}

/// a * b = x + y exactly (Dekker's TwoProduct).
inline void two_product(double a, double b, double& x, double& y) {
    x = a * b;
    double a_high, a_low, b_high, b_low;
    split(a, a_high, a_low);
    split(b, b_high, b_low);
    y = a_low * b_low - (((x - a_high * b_high) - a_low * b_high) - a_high * b_low);
}

/// An expansion of at most N components: nonoverlapping, increasing magnitude, no zeros.
/// The capacity is a template argument so that each intermediate has its exact worst-case
/// size (a difference 2, a product of differences 8, a 2x2 minor 16, ... the 3x3 determinant 192).
template <int N>
struct Expansion {
    double c[N];
    int n = 0;
    void push(double value) {
        if (value != 0) c[n++] = value;
    }
};

Expansion<2> difference(double a, double b) {
    Expansion<2> e;
    double x, y;
    two_sum(a, -b, x, y);
    e.push(y);
    e.push(x);
    return e;
}

/// e * b (Shewchuk's Scale-Expansion with zero elimination).
template <int N>
Expansion<2 * N> scale(const Expansion<N>& e, double b) {
    Expansion<2 * N> h;
    if (e.n == 0 || b == 0) return h;
    double q, t;
    two_product(e.c[0], b, q, t);
    h.push(t);
    for (int i = 1; i < e.n; ++i) {
        double p_high, p_low, sum, err;
        two_product(e.c[i], b, p_high, p_low);
        two_sum(q, p_low, sum, err);
        h.push(err);
        two_sum(p_high, sum, q, err);
        h.push(err);
    }
    h.push(q);
    return h;
}

/// e + f (Shewchuk's Fast-Expansion-Sum: merge by magnitude, then accumulate with TwoSum).
template <int N, int M>
Expansion<N + M> sum(const Expansion<N>& e, const Expansion<M>& f) {
    double merged[N + M];
    int i = 0, j = 0, m = 0;
    while (i < e.n && j < f.n) merged[m++] = std::fabs(e.c[i]) < std::fabs(f.c[j]) ? e.c[i++] : f.c[j++];
    while (i < e.n) merged[m++] = e.c[i++];
    while (j < f.n) merged[m++] = f.c[j++];
    Expansion<N + M> h;
    if (m == 0) return h;
    double q = merged[0];
    for (int k = 1; k < m; ++k) {
        double next, err;
        two_sum(q, merged[k], next, err);
        h.push(err);
        q = next;
    }
    h.push(q);
    return h;
}

template <int N>
Expansion<N> negate(Expansion<N> e) {
    for (int i = 0; i < e.n; ++i) e.c[i] = -e.c[i];
    return e;
}

/// e * f for a difference f (two components at most).
template <int N>
Expansion<4 * N> product(const Expansion<N>& e, const Expansion<2>& f) {
    if (f.n == 0) return {};
    if (f.n == 1) {
        Expansion<4 * N> h;
        const Expansion<2 * N> single = scale(e, f.c[0]);
        std::copy(single.c, single.c + single.n, h.c);
        h.n = single.n;
        return h;
    }
    return sum(scale(e, f.c[0]), scale(e, f.c[1]));
}

/// Error-free steps of a plain evaluation: each returns false when its result was rounded.
/// Meshes on grids (integer or few-bit coordinates) are evaluated exactly in double this way,
/// which settles their many exactly coplanar cases without expansions.
bool exact_add(double a, double b, double& x) {
    double tail;
    two_sum(a, b, x, tail);
    return tail == 0;
}
bool exact_multiply(double a, double b, double& x) {
    double tail;
    two_product(a, b, x, tail);
    return tail == 0;
}
/// a * b - c * d without rounding, or false.
bool exact_cross(double a, double b, double c, double d, double& x) {
    double ab, cd;
    return exact_multiply(a, b, ab) && exact_multiply(c, d, cd) && exact_add(ab, -cd, x);
}

template <int N>
int sign_of(const Expansion<N>& e) {
    return e.n == 0 ? 0 : (e.c[e.n - 1] > 0 ? 1 : -1);
}

int sign_of(double value) { return (value > 0) - (value < 0); }

/// Exact (b - a) x (c - a) in 2D: (bx - ax)(cy - ay) - (by - ay)(cx - ax).
Expansion<16> exact_cross2(double ax, double ay, double bx, double by, double cx, double cy) {
    return sum(product(difference(bx, ax), difference(cy, ay)), negate(product(difference(by, ay), difference(cx, ax))));
}

/// The sign of orient3d when the plain double evaluation has no rounding at all.
bool orient3d_if_exact_in_double(const Point3& a, const Point3& b, const Point3& c, const Point3& d, int& sign) {
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; ++k) {
        if (!exact_add(b[k], -a[k], u[k]) || !exact_add(c[k], -a[k], v[k]) || !exact_add(d[k], -a[k], w[k])) return false;
    }
    double m1, m2, m3, t1, t2, t3, s12, det;
    if (!exact_cross(u[1], v[2], u[2], v[1], m1) || !exact_cross(u[2], v[0], u[0], v[2], m2) ||
        !exact_cross(u[0], v[1], u[1], v[0], m3)) {
        return false;
    }
    if (!exact_multiply(w[0], m1, t1) || !exact_multiply(w[1], m2, t2) || !exact_multiply(w[2], m3, t3)) return false;
    if (!exact_add(t1, t2, s12) || !exact_add(s12, t3, det)) return false;
    sign = sign_of(det);
    return true;
}

}  // namespace

int orient2d(const Point2& a, const Point2& b, const Point2& c) {
    const double left = (b[0] - a[0]) * (c[1] - a[1]);
    const double right = (b[1] - a[1]) * (c[0] - a[0]);
    const double det = left - right;
    const double bound = kOrient2dBound * (std::fabs(left) + std::fabs(right));
    if (std::fabs(det) > bound) return sign_of(det);
    double ux, uy, vx, vy, exact;
    if (exact_add(b[0], -a[0], ux) && exact_add(b[1], -a[1], uy) && exact_add(c[0], -a[0], vx) &&
        exact_add(c[1], -a[1], vy) && exact_cross(ux, vy, uy, vx, exact)) {
        return sign_of(exact);
    }
    return sign_of(exact_cross2(a[0], a[1], b[0], b[1], c[0], c[1]));
}

int orient3d(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
    // det[b - a; c - a; d - a] expanded along d - a.
    const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    const double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
    const double m1 = uy * vz - uz * vy, m2 = uz * vx - ux * vz, m3 = ux * vy - uy * vx;
    const double det = wx * m1 + wy * m2 + wz * m3;
    const double permanent = std::fabs(wx) * (std::fabs(uy * vz) + std::fabs(uz * vy)) +
                             std::fabs(wy) * (std::fabs(uz * vx) + std::fabs(ux * vz)) +
                             std::fabs(wz) * (std::fabs(ux * vy) + std::fabs(uy * vx));
    if (std::fabs(det) > kOrient3dBound * permanent) return sign_of(det);
    if (int sign = 0; orient3d_if_exact_in_double(a, b, c, d, sign)) return sign;

    const Expansion<16> m1_exact = exact_cross2(a[1], a[2], b[1], b[2], c[1], c[2]);
    const Expansion<16> m2_exact = exact_cross2(a[2], a[0], b[2], b[0], c[2], c[0]);
    const Expansion<16> m3_exact = exact_cross2(a[0], a[1], b[0], b[1], c[0], c[1]);
    const Expansion<128> partial = sum(product(m1_exact, difference(d[0], a[0])), product(m2_exact, difference(d[1], a[1])));
    return sign_of(sum(partial, product(m3_exact, difference(d[2], a[2]))));
}

bool collinear(const Point3& a, const Point3& b, const Point3& c) {
    // The cross product is zero exactly when its three projections are.
    return orient2d({a[0], a[1]}, {b[0], b[1]}, {c[0], c[1]}) == 0 &&
           orient2d({a[1], a[2]}, {b[1], b[2]}, {c[1], c[2]}) == 0 &&
           orient2d({a[2], a[0]}, {b[2], b[0]}, {c[2], c[0]}) == 0;
}

}  // namespace vdbmesh::detail
