#pragma once
// Private: the ONE rule for inside/outside and for where the surface crosses an edge, shared
// by Marching Cubes (marching_cubes.cpp) and Dual Marching Cubes (dmc_*.cpp) so that DMC at
// error 0 reproduces MC bit for bit.
//
// - A sample's signed value is s = f - iso (Inside::above) or iso - f (Inside::below);
//   the sample is inside iff s > 0 (a value equal to the isovalue counts as outside).
// - Samples outside the scanned box (kMetaScanMin/Max) get s = kOutsideScan (-infinity):
//   outside the object. An edge from a finite value to kOutsideScan is crossed at its
//   midpoint, so the surface closes half a voxel beyond the last sample (the voxel's face).
// - Otherwise the crossing parameter is t = s0 / (s0 - s1), clamped to
//   [kCrossingMargin, 1 - kCrossingMargin]: with isovalues equal to sample values (integer
//   iso on integer CT) no mesh vertex lands on a sample, so no two vertices coincide and
//   no triangle has zero area.
// - The point is interpolated from the lexicographically smaller end (z, then y, then x),
//   in double, so both meshers get the same bits whichever way they walk the edge.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace vdbmesh::detail {

inline constexpr double kCrossingMargin = 1e-3;
inline constexpr double kOutsideScan = -std::numeric_limits<double>::infinity();

/// Signed value of sample @a value: positive inside the object.
inline double signed_value(float value, double iso, bool inside_above) {
    return inside_above ? double(value) - iso : iso - double(value);
}

inline bool is_inside(double signed_value) { return signed_value > 0.0; }

/// Where along the edge from s0 (t = 0) to s1 (t = 1) the surface crosses; s0 and s1 lie on
/// different sides.
inline double crossing_parameter(double s0, double s1) {
    if (std::isinf(s0) || std::isinf(s1)) return 0.5;
    const double t = s0 / (s0 - s1);
    return std::min(std::max(t, kCrossingMargin), 1.0 - kCrossingMargin);
}

using Point3d = std::array<double, 3>;

inline bool lexicographically_less(const Point3d& a, const Point3d& b) {
    if (a[2] != b[2]) return a[2] < b[2];
    if (a[1] != b[1]) return a[1] < b[1];
    return a[0] < b[0];
}

/// The surface point on the segment p0-p1 (index space) with signed values s0 and s1.
inline Point3d edge_crossing(Point3d p0, double s0, Point3d p1, double s1) {
    if (lexicographically_less(p1, p0)) {
        std::swap(p0, p1);
        std::swap(s0, s1);
    }
    const double t = crossing_parameter(s0, s1);
    return {p0[0] + t * (p1[0] - p0[0]), p0[1] + t * (p1[1] - p0[1]), p0[2] + t * (p1[2] - p0[2])};
}

}  // namespace vdbmesh::detail
