// Exact orientation predicates after J. R. Shewchuk, "Adaptive Precision Floating-Point
// Arithmetic and Fast Robust Geometric Predicates", Discrete Comput. Geom. 18 (1997) 305-363:
// a floating-point evaluation whose error bound decides almost every call, and otherwise the
// exact value as a nonoverlapping expansion (a sum of doubles) whose sign is that of its
// largest component. Differences are kept exact (two-term expansions), so the result is exact
// for any finite double input. Needs IEEE round-to-nearest doubles without extended precision
// (x86-64 SSE) and no contraction into fused multiply-adds (ISO C++ mode).
#include "analysis/exact_predicates.h"

#include <cmath>

namespace vdbmesh::detail {
namespace {

// Expansion lengths: a difference has 2 components, a product of two differences 8, a 2x2
// minor 16, a minor times a difference 64, the 3x3 determinant 192.
constexpr int kMaxComponents = 192;

// Bounds on the relative error of the plain floating-point determinants, with margin over
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

/// An expansion in a fixed buffer: components nonoverlapping, increasing magnitude, no zeros.
struct Expansion {
    double c[kMaxComponents];
    int n = 0;
};

Expansion difference(double a, double b) {
    Expansion e;
    double x, y;
    two_sum(a, -b, x, y);
    if (y != 0) e.c[e.n++] = y;
    if (x != 0) e.c[e.n++] = x;
    return e;
}

/// e * b (Shewchuk's Scale-Expansion with zero elimination).
Expansion scale(const Expansion& e, double b) {
    Expansion h;
    if (e.n == 0 || b == 0) return h;
    double q, t;
    two_product(e.c[0], b, q, t);
    if (t != 0) h.c[h.n++] = t;
    for (int i = 1; i < e.n; ++i) {
        double p_high, p_low, sum, err;
        two_product(e.c[i], b, p_high, p_low);
        two_sum(q, p_low, sum, err);
        if (err != 0) h.c[h.n++] = err;
        two_sum(p_high, sum, q, err);
        if (err != 0) h.c[h.n++] = err;
    }
    if (q != 0) h.c[h.n++] = q;
    return h;
}

/// e + f (Shewchuk's Fast-Expansion-Sum: merge by magnitude, then accumulate with TwoSum).
Expansion sum(const Expansion& e, const Expansion& f) {
    double merged[kMaxComponents];
    int i = 0, j = 0, m = 0;
    while (i < e.n && j < f.n) merged[m++] = std::fabs(e.c[i]) < std::fabs(f.c[j]) ? e.c[i++] : f.c[j++];
    while (i < e.n) merged[m++] = e.c[i++];
    while (j < f.n) merged[m++] = f.c[j++];
    Expansion h;
    if (m == 0) return h;
    double q = merged[0];
    for (int k = 1; k < m; ++k) {
        double next, err;
        two_sum(q, merged[k], next, err);
        if (err != 0) h.c[h.n++] = err;
        q = next;
    }
    if (q != 0) h.c[h.n++] = q;
    return h;
}

Expansion negate(Expansion e) {
    for (int i = 0; i < e.n; ++i) e.c[i] = -e.c[i];
    return e;
}

Expansion product(const Expansion& e, const Expansion& f) {
    Expansion h;
    for (int i = 0; i < f.n; ++i) h = sum(h, scale(e, f.c[i]));
    return h;
}

int sign_of(const Expansion& e) { return e.n == 0 ? 0 : (e.c[e.n - 1] > 0 ? 1 : -1); }

int sign_of(double value) { return (value > 0) - (value < 0); }

/// Exact (b - a) x (c - a) in 2D: (bx - ax)(cy - ay) - (by - ay)(cx - ax).
Expansion exact_cross2(double ax, double ay, double bx, double by, double cx, double cy) {
    const Expansion left = product(difference(bx, ax), difference(cy, ay));
    const Expansion right = product(difference(by, ay), difference(cx, ax));
    return sum(left, negate(right));
}

}  // namespace

int orient2d(const Point2& a, const Point2& b, const Point2& c) {
    const double left = (b[0] - a[0]) * (c[1] - a[1]);
    const double right = (b[1] - a[1]) * (c[0] - a[0]);
    const double det = left - right;
    const double bound = kOrient2dBound * (std::fabs(left) + std::fabs(right));
    if (std::fabs(det) > bound) return sign_of(det);
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

    const Expansion eux = difference(b[0], a[0]), euy = difference(b[1], a[1]), euz = difference(b[2], a[2]);
    const Expansion evx = difference(c[0], a[0]), evy = difference(c[1], a[1]), evz = difference(c[2], a[2]);
    const Expansion em1 = sum(product(euy, evz), negate(product(euz, evy)));
    const Expansion em2 = sum(product(euz, evx), negate(product(eux, evz)));
    const Expansion em3 = sum(product(eux, evy), negate(product(euy, evx)));
    Expansion total = product(em1, difference(d[0], a[0]));
    total = sum(total, product(em2, difference(d[1], a[1])));
    total = sum(total, product(em3, difference(d[2], a[2])));
    return sign_of(total);
}

bool collinear(const Point3& a, const Point3& b, const Point3& c) {
    // The cross product is zero exactly when its three projections are.
    return orient2d({a[0], a[1]}, {b[0], b[1]}, {c[0], c[1]}) == 0 &&
           orient2d({a[1], a[2]}, {b[1], b[2]}, {c[1], c[2]}) == 0 &&
           orient2d({a[2], a[0]}, {b[2], b[0]}, {c[2], c[0]}) == 0;
}

}  // namespace vdbmesh::detail
