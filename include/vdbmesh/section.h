#pragma once
/// @file section.h
/// @brief Cross-sections of the solid a closed mesh bounds: the cut by a plane as nested closed
/// loops, with its area, perimeter, centroid and second moments (OpenVDB-free; `vdbmesh section`).

#include <array>
#include <cstddef>
#include <vector>

#include "vdbmesh/mesh.h"

namespace vdbmesh {

/// The points x with dot(normal, x) == offset; normal is a unit vector (make_plane()).
struct Plane {
    std::array<double, 3> normal{0, 0, 1};
    double offset = 0;
};

/// @brief The plane through the points whose coordinate @a axis (0 x, 1 y, 2 z) is @a value.
Plane axis_plane(int axis, double value);

/// @brief The plane dot(normal / |normal|, x) == @a offset.
/// @throw UsageError when @a normal is zero or not finite, or @a offset not finite.
Plane make_plane(const std::array<double, 3>& normal, double offset);

/// One closed polyline of a section (its last point joins its first).
struct SectionLoop {
    std::vector<std::array<double, 3>> points;  ///< in world coordinates, on the plane
    /// Signed, in the plane's (u, v) frame: positive for an outer boundary (counter-clockwise
    /// seen from the side the normal points to), negative for a hole.
    double area = 0;
    double perimeter = 0;
    int depth = 0;    ///< loops enclosing it: 0 outermost; odd depths are holes
    int parent = -1;  ///< index of the innermost loop enclosing it, -1 when none
};

/// The section of a solid by one plane. In-plane coordinates are (u, v) = (dot(u_axis, x),
/// dot(v_axis, x)), a right-handed frame with cross(u_axis, v_axis) = plane.normal: for the
/// plane z = c it is (x, y), for x = c (y, z), for y = c (z, x).
struct Section {
    Plane plane;
    std::array<double, 3> u_axis{}, v_axis{};
    std::vector<SectionLoop> loops;  ///< largest |area| first; parents before their children
    double area = 0;       ///< of the material: outer loops minus holes
    double perimeter = 0;  ///< of all loops
    std::array<double, 3> centroid{};  ///< of the material's area (world); the plane's point nearest the origin when area is 0
    /// Second moments of the material's area about the centroid, in the (u, v) frame:
    /// [integral of v^2, integral of u^2, integral of u v] (world units^4).
    std::array<double, 3> second_moments{};
    std::size_t holes() const;  ///< loops of odd depth
};

/// @brief The section of the solid bounded by @a mesh with @a plane. A vertex exactly on the
/// plane counts as lying on the side the normal points to, so every crossing of the surface
/// with the plane is a proper polyline even through vertices and edges lying in the plane.
/// @throw Error when the mesh is not closed and consistently oriented along the cut (a crossing
/// edge that does not belong to exactly one triangle on each side), or has a missing vertex.
Section section_mesh(const Mesh& mesh, const Plane& plane);

}  // namespace vdbmesh
