#pragma once
// Private: the figures of a section (areas, moments, nesting) from its loops of points.

#include <array>
#include <vector>

#include "vdbmesh/section.h"

namespace vdbmesh::detail {

/// The Section of @a plane whose loops are @a loops (closed polylines on the plane, outer ones
/// counter-clockwise seen from the normal's side, holes clockwise).
Section section_from_loops(const Plane& plane, std::vector<std::vector<std::array<double, 3>>> loops);

}  // namespace vdbmesh::detail
