// The vertex of a unit cell of the dual mesh: the mass point of its crossings projected onto
// the trilinear isosurface.

#include "mesh/unit_cell_vertex.h"

#include <algorithm>
#include <cmath>

#include "mesh/ifc_fan.h"

namespace vdbmesh::detail {

namespace {

/// Newton steps: the trilinear field is smooth and the mass point lies near its surface, so a
/// few steps reach it to well under float rounding of the output.
constexpr int kNewtonSteps = 4;
/// A step shorter than this (voxels) ends the walk: far below the output's float rounding.
constexpr double kConverged = 1e-6;

}  // namespace

Point3d unit_cell_vertex(const std::array<double, 8>& corner_values, const Point3d& mass_point, double iso) {
    Point3d t = mass_point;
    for (int step = 0; step < kNewtonSteps; ++step) {
        const TrilinearSample s = trilinear_sample(corner_values, t);
        if (!s.finite) break;
        const Point3d& g = s.gradient;
        const double g2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
        if (!(g2 > 0)) break;
        const double scale = (s.value - iso) / g2;
        for (int a = 0; a < 3; ++a) t[a] = std::clamp(t[a] - scale * g[a], 0.0, 1.0);
        if (scale * scale * g2 < kConverged * kConverged) break;  // the step was that short
    }
    for (double& c : t) c = std::clamp(c, kUnitVertexMargin, 1.0 - kUnitVertexMargin);
    return t;
}

}  // namespace vdbmesh::detail
