#pragma once
// Private to the decimator (decimate_*.cpp): the vector and box helpers its parts share,
// and the slab of its intersection proof.

#include <algorithm>
#include <array>
#include <limits>

#include "process/quadric.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/separating_plane.h"

namespace vdbmesh::detail::decimation {

using Box = detail::Box;
using FloatTriangle = std::array<std::array<float, 3>, 3>;
constexpr std::uint32_t kNone = ~0u;

inline Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3d cross(const Vec3d& a, const Vec3d& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
inline double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3d to_double(const std::array<float, 3>& p) { return {p[0], p[1], p[2]}; }
inline std::array<float, 3> to_float(const Vec3d& p) { return {float(p[0]), float(p[1]), float(p[2])}; }
inline detail::Triangle3 to_double(const FloatTriangle& t) { return {to_double(t[0]), to_double(t[1]), to_double(t[2])}; }

inline Box empty_box() {
    constexpr float inf = std::numeric_limits<float>::infinity();
    return {{inf, inf, inf}, {-inf, -inf, -inf}};
}
inline bool holds_nothing(const Box& box) { return !(box.lo[0] <= box.hi[0]); }  ///< (as empty_box())
inline void grow(Box& box, const std::array<float, 3>& p) {
    for (int k = 0; k < 3; ++k) box.lo[k] = std::min(box.lo[k], p[k]), box.hi[k] = std::max(box.hi[k], p[k]);
}

/// The points between two planes across an axis, as far apart as the points added need (each
/// widened by the rounding of its distance along the axis, so a point added is certainly within).
struct Slab {
    Vec3d axis{}, origin{};
    double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
    void add(const Vec3d& p) {
        const detail::SignedDistance d = detail::along(axis, origin, p);
        lo = std::min(lo, d.value - d.error), hi = std::max(hi, d.value + d.error);
    }
    /// Whether the points of @a t certainly all lie beyond one of the planes (then the triangle
    /// misses the slab).
    bool misses(const FloatTriangle& t) const {
        int below = 0, above = 0;
        for (const auto& q : t) {
            const detail::SignedDistance d = detail::along(axis, origin, to_double(q));
            below += d.value + d.error < lo, above += d.value - d.error > hi;
        }
        return below == 3 || above == 3;
    }
};


}  // namespace vdbmesh::detail::decimation
