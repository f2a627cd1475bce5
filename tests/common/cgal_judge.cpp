// CGAL as the independent judge of closedness, manifoldness, orientation, degeneracy and
// self-intersection (see cgal_judge.h). The triangles go in as a polygon soup with the mesh's
// own vertex indices: if CGAL cannot build a halfedge mesh from them as they are, the mesh is
// not a manifold, consistently oriented surface, and nothing else is judged.

#include "cgal_judge.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <sstream>
#include <vector>

namespace vdbmesh::test {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

}  // namespace

std::string CgalVerdict::describe() const {
    std::ostringstream out;
    out << "CGAL: " << (polygon_mesh ? "manifold and oriented" : "NOT a manifold oriented surface") << ", "
        << (closed ? "closed" : "NOT closed") << ", " << (outward ? "outward" : "NOT outward") << ", "
        << (self_intersects ? "SELF-INTERSECTING" : "no self-intersection") << ", " << degenerate_faces
        << " degenerate faces, volume " << volume;
    return out.str();
}

CgalVerdict judge_with_cgal(const Mesh& mesh) {
    CgalVerdict verdict;
    if (mesh.triangles.empty()) {
        verdict = {true, true, true, false, 0, 0.0};
        return verdict;
    }
    std::vector<Kernel::Point_3> points;
    points.reserve(mesh.vertices.size());
    for (const auto& v : mesh.vertices) points.emplace_back(v[0], v[1], v[2]);
    std::vector<std::vector<std::size_t>> polygons;
    polygons.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) polygons.push_back({t[0], t[1], t[2]});
    verdict.polygon_mesh = PMP::is_polygon_soup_a_polygon_mesh(polygons);
    if (!verdict.polygon_mesh) return verdict;
    SurfaceMesh surface;
    PMP::polygon_soup_to_polygon_mesh(points, polygons, surface);
    verdict.closed = CGAL::is_closed(surface);
    for (auto face : surface.faces()) verdict.degenerate_faces += PMP::is_degenerate_triangle_face(face, surface);
    verdict.self_intersects = PMP::does_self_intersect<CGAL::Parallel_if_available_tag>(surface);
    // Outward: every component oriented as its nesting asks (outer shells out, pores in:
    // does_bound_a_volume, defined for closed meshes without self-intersection), and the
    // enclosed volume positive, which rules out a mesh turned inside out as a whole.
    if (verdict.closed && !verdict.self_intersects) {
        verdict.volume = PMP::volume(surface);
        verdict.outward = PMP::does_bound_a_volume(surface) && verdict.volume > 0;
    }
    return verdict;
}

}  // namespace vdbmesh::test
