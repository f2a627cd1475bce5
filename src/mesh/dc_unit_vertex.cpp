// The vertex of a unit cell at error 0 (dc_unit_vertex.h).

#include "mesh/dc_unit_vertex.h"

#include <algorithm>
#include <cmath>

namespace vdbmesh::detail {

namespace {

/// Newton steps towards the isosurface: the trilinear interpolant is smooth within a cell, and
/// a start on the crossings' tangent planes is within a small part of a voxel of it, so a
/// few steps land on it to well under the float rounding of the output.
constexpr int kNewtonSteps = 4;

}  // namespace

Point3d unit_cell_vertex(const std::array<double, 8>& values, double iso, const Point3d& start, const Point3d& lo, const Point3d& hi) {
    Point3d p;
    for (int a = 0; a < 3; ++a) p[a] = std::clamp(start[a], lo[a], hi[a]);
    for (const double value : values) {
        if (!std::isfinite(value)) return p;
    }
    for (int step = 0; step < kNewtonSteps; ++step) {
        double f = -iso;
        Point3d g = {0, 0, 0};
        for (int c = 0; c < 8; ++c) {
            const int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
            const double wx = dx ? p[0] : 1 - p[0], wy = dy ? p[1] : 1 - p[1], wz = dz ? p[2] : 1 - p[2];
            f += wx * wy * wz * values[c];
            g[0] += (dx ? 1 : -1) * wy * wz * values[c];
            g[1] += (dy ? 1 : -1) * wx * wz * values[c];
            g[2] += (dz ? 1 : -1) * wx * wy * values[c];
        }
        const double g2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
        if (!(g2 > 0)) break;
        for (int a = 0; a < 3; ++a) p[a] = std::clamp(p[a] - f * g[a] / g2, lo[a], hi[a]);
    }
    return p;
}

}  // namespace vdbmesh::detail
