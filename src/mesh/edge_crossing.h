#pragma once
// Private: the ONE rule for inside/outside and for where the surface crosses an edge, shared
// by Marching Cubes (marching_cubes.cpp) and intersection-free DC (dc_*.cpp) so that DC at
// error 0 reproduces MC bit for bit.
//
// - A sample is inside iff its value is strictly above the isovalue (Inside::above) or strictly
//   below it (Inside::below): a value equal to the isovalue counts as outside.
// - Samples outside the scanned box (kMetaScanMin/Max) are outside the object; the meshers give
//   them the value outside_scan_value() (an infinity on the outside side). An edge with such an
//   end is crossed at its midpoint, so the surface closes half a voxel beyond the last sample
//   (on the voxel's face).
// - Otherwise the crossing parameter is t = (iso - f0) / (f1 - f0), clamped to
//   [kCrossingMargin, 1 - kCrossingMargin]: with isovalues equal to sample values (integer
//   iso on integer CT) no mesh vertex lands on a sample, so no two vertices coincide and
//   no triangle has zero area.
// - The point is interpolated from the lexicographically smaller end (z, then y, then x) as
//   p0 + t (p1 - p0), in double, so both meshers get the same bits whichever way they walk
//   the edge (for a grid edge from voxel p along an axis: p + t on that axis).

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace vdbmesh::detail {

inline constexpr double kCrossingMargin = 1e-3;

/// Whether a (finite or infinite) value is inside the object.
inline bool is_inside_value(double value, double iso, bool inside_above) {
    return inside_above ? value > iso : value < iso;
}

/// The value standing for samples outside the scanned box: outside the object.
inline double outside_scan_value(bool inside_above) {
    return inside_above ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
}

/// Where along the edge from value f0 (t = 0) to f1 (t = 1) the isosurface crosses; f0 and f1
/// lie on different sides of @a iso. Kept @a margin (at least kCrossingMargin) from the ends.
inline double crossing_parameter(double f0, double f1, double iso, double margin = kCrossingMargin) {
    if (std::isinf(f0) || std::isinf(f1)) return 0.5;
    margin = std::max(margin, kCrossingMargin);
    return std::clamp((iso - f0) / (f1 - f0), margin, 1.0 - margin);
}

using Point3d = std::array<double, 3>;

inline double squared_distance(const Point3d& a, const Point3d& b) {
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

inline bool lexicographically_less(const Point3d& a, const Point3d& b) {
    if (a[2] != b[2]) return a[2] < b[2];
    if (a[1] != b[1]) return a[1] < b[1];
    return a[0] < b[0];
}

/// The surface point on the segment p0-p1 (index space) whose ends hold values f0 and f1, kept
/// @a margin of the segment from its ends.
inline Point3d edge_crossing(Point3d p0, double f0, Point3d p1, double f1, double iso, double margin = kCrossingMargin) {
    if (lexicographically_less(p1, p0)) {
        std::swap(p0, p1);
        std::swap(f0, f1);
    }
    const double t = crossing_parameter(f0, f1, iso, margin);
    return {p0[0] + t * (p1[0] - p0[0]), p0[1] + t * (p1[1] - p0[1]), p0[2] + t * (p1[2] - p0[2])};
}

}  // namespace vdbmesh::detail
