// section_mesh(): the cut of a closed mesh by a plane, its triangles cut one by one
// (section_cut.cpp), the segments chained into loops. Figures: section_figures.cpp.
#include <cmath>
#include <string>

#include "analysis/section_cut.h"
#include "analysis/section_figures.h"
#include "vdbmesh/error.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/section.h"

namespace vdbmesh {

Plane axis_plane(int axis, double value) {
    if (axis < 0 || axis > 2) throw UsageError("plane axis: expected 0, 1 or 2, got " + std::to_string(axis));
    Plane plane;
    plane.normal = {0, 0, 0};
    plane.normal[axis] = 1;
    plane.offset = value;
    return plane;
}

Plane make_plane(const std::array<double, 3>& normal, double offset) {
    const double length = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    if (!(length > 0) || !std::isfinite(length)) throw UsageError("plane normal: expected a finite non-zero vector");
    if (!std::isfinite(offset)) throw UsageError("plane offset: expected a finite number");
    return Plane{{normal[0] / length, normal[1] / length, normal[2] / length}, offset};
}

Section section_mesh(const Mesh& mesh, const Plane& plane) {
    detail::check_indices(mesh);
    std::vector<detail::CutSegment> segments;
    for (const auto& t : mesh.triangles) {
        const std::array<std::array<float, 3>, 3> corners{mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
        detail::cut_triangle(plane, detail::numbered_triangle(t, corners), segments);
    }
    return detail::section_from_loops(plane, detail::chain_loops(std::move(segments), true));
}

}  // namespace vdbmesh
