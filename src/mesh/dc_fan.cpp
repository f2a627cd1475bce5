// The accuracy tests of merged cells: the fan a cell will be, and the trilinear estimate.

#include "mesh/dc_fan.h"

#include <cmath>
#include <limits>

namespace vdbmesh::detail {

void IfcFan::add_chord(const Point3d& a, const Point3d& b) {
    const Point3d middle = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
    triangles_[count_++] = {vertex_, a, middle};
    triangles_[count_++] = {vertex_, middle, b};
}

bool IfcFan::near(const Point3d& p, double distance) {
    const double limit = distance * distance;
    for (int k = 0; k < count_; ++k) {
        const int t = (last_near_ + k) % count_;
        const Point3d q = closest_point_on_triangle(p, triangles_[t][0], triangles_[t][1], triangles_[t][2]);
        const double d2 = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]);
        if (d2 <= limit) {
            last_near_ = t;
            return true;
        }
    }
    return false;
}

double trilinear_surface_distance(const std::array<double, 8>& values, const std::array<double, 3>& t, double iso) {
    double f = 0;
    Point3d g = {0, 0, 0};
    for (int c = 0; c < 8; ++c) {
        const int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
        const double value = values[c];
        if (!std::isfinite(value)) return 0;
        const double wx = dx ? t[0] : 1 - t[0], wy = dy ? t[1] : 1 - t[1], wz = dz ? t[2] : 1 - t[2];
        f += wx * wy * wz * value;
        g[0] += (dx ? 1 : -1) * wy * wz * value;
        g[1] += (dy ? 1 : -1) * wx * wz * value;
        g[2] += (dz ? 1 : -1) * wx * wy * value;
    }
    const double length = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    return length > 0 ? std::abs(f - iso) / length : std::numeric_limits<double>::infinity();
}

}  // namespace vdbmesh::detail
