#pragma once
// The independent judge of the mesh guarantees: CGAL's Polygon_mesh_processing (Debian
// libcgal-dev, test-only). The guarantee tests judge the meshers with it, not with
// analyze_mesh(), which Dual Marching Cubes' own checks are built from. This header keeps CGAL
// out of the tests that include it; only cgal_judge.cpp compiles CGAL.

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "vdbmesh/mesh.h"

namespace vdbmesh::test {

struct CgalVerdict {
    bool polygon_mesh = false;         ///< manifold and consistently oriented (is_polygon_soup_a_polygon_mesh)
    bool closed = false;               ///< no border edge (CGAL::is_closed)
    bool outward = false;              ///< bounds a volume (PMP::does_bound_a_volume) with volume > 0
    bool self_intersects = true;       ///< PMP::does_self_intersect
    std::size_t degenerate_faces = 0;  ///< PMP::is_degenerate_triangle_face (exactly collinear corners)
    double volume = 0.0;               ///< PMP::volume, in the mesh's units
    bool clean() const { return polygon_mesh && closed && outward && !self_intersects && degenerate_faces == 0; }
    std::string describe() const;
};

/// What CGAL finds in @a mesh (an empty mesh is judged clean). Nothing is repaired.
CgalVerdict judge_with_cgal(const Mesh& mesh);

}  // namespace vdbmesh::test

namespace vdbmesh::test {

/// Pairs of triangles of @a soup (any triangle set, e.g. all labels' walls, each once) that meet
/// beyond the corners they share by index, decided with CGAL's exact predicates (box
/// intersection, then Kernel::Do_intersect_3 and orientation tests): no shared corner, any
/// common point; one, the opposite side of either crossing the other triangle; two, coplanar and
/// on the same side of the edge; three, always. Degenerate triangles are counted apart.
struct CgalCrossings {
    std::size_t pairs = 0;
    std::size_t degenerate = 0;
};
CgalCrossings cgal_crossings(const Mesh& soup);
/// The crossing pairs themselves (triangle indices, i < j), in no particular order.
std::vector<std::pair<std::size_t, std::size_t>> cgal_crossing_pairs(const Mesh& soup);

}  // namespace vdbmesh::test
