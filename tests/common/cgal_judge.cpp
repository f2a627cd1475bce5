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
#include <CGAL/box_intersection_d.h>
#include <CGAL/boost/graph/helpers.h>

#include <array>
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
    // Fixed-size polygons: CGAL takes any random-access range as a polygon, and a vector each
    // was a heap allocation a triangle (millions on a whole scan).
    std::vector<std::array<std::size_t, 3>> polygons;
    polygons.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) polygons.push_back({t[0], t[1], t[2]});
    verdict.polygon_mesh = PMP::is_polygon_soup_a_polygon_mesh(polygons);
    if (!verdict.polygon_mesh) return verdict;
    SurfaceMesh surface;
    PMP::polygon_soup_to_polygon_mesh(points, polygons, surface);
    verdict.closed = CGAL::is_closed(surface);
    for (auto face : surface.faces()) verdict.degenerate_faces += PMP::is_degenerate_triangle_face(face, surface);
    // Sequential: CGAL's parallel box intersection (CGAL 5.5, box_intersection_d.h) copies the
    // boxes four times and intersects 16 pairs of quarters, about four times the sequential
    // sorting and tree work; the suite runs two tests at a time on two cores, so that work
    // had no idle core to go to (Seg3dMrNifti's test spent most of its time there).
    verdict.self_intersects = PMP::does_self_intersect<CGAL::Sequential_tag>(surface);
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


namespace vdbmesh::test {
namespace {

bool triangles_cross(const Mesh& soup, std::size_t i, std::size_t j) {
    const auto& a = soup.triangles[i];
    const auto& b = soup.triangles[j];
    const auto point = [&](std::uint32_t v) {
        return Kernel::Point_3(soup.vertices[v][0], soup.vertices[v][1], soup.vertices[v][2]);
    };
    int shared = 0, a_shared[3] = {-1, -1, -1};
    for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q)
            if (a[p] == b[q]) a_shared[p] = q, ++shared;
    const Kernel::Triangle_3 ta(point(a[0]), point(a[1]), point(a[2])), tb(point(b[0]), point(b[1]), point(b[2]));
    if (shared == 0) return CGAL::do_intersect(ta, tb);
    if (shared == 3) return true;
    if (shared == 1) {
        const int p = int(std::find_if(a_shared, a_shared + 3, [](int q) { return q >= 0; }) - a_shared), q = a_shared[p];
        const Kernel::Segment_3 opposite_a(point(a[(p + 1) % 3]), point(a[(p + 2) % 3]));
        const Kernel::Segment_3 opposite_b(point(b[(q + 1) % 3]), point(b[(q + 2) % 3]));
        return CGAL::do_intersect(opposite_a, tb) || CGAL::do_intersect(opposite_b, ta);
    }
    // A shared edge: they overlap when coplanar with the two far corners on the same side.
    const int p = int(std::find(a_shared, a_shared + 3, -1) - a_shared);
    std::uint32_t far_b = 0;
    for (int q = 0; q < 3; ++q)
        if (b[q] != a[(p + 1) % 3] && b[q] != a[(p + 2) % 3]) far_b = b[q];
    const Kernel::Point_3 e0 = point(a[(p + 1) % 3]), e1 = point(a[(p + 2) % 3]), fa = point(a[p]), fb = point(far_b);
    return CGAL::orientation(e0, e1, fa, fb) == CGAL::COPLANAR && CGAL::coplanar_orientation(e0, e1, fa, fb) == CGAL::POSITIVE;
}

/// Candidate pairs (overlapping boxes) of the non-degenerate triangles; counts the degenerate ones.
std::vector<std::pair<std::size_t, std::size_t>> box_pairs(const Mesh& soup, std::size_t& degenerate) {
    using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
    std::vector<Box> boxes;
    for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
        const auto& tri = soup.triangles[t];
        const auto point = [&](int k) {
            return Kernel::Point_3(soup.vertices[tri[k]][0], soup.vertices[tri[k]][1], soup.vertices[tri[k]][2]);
        };
        if (CGAL::collinear(point(0), point(1), point(2))) {
            ++degenerate;
            continue;
        }
        boxes.emplace_back(point(0).bbox() + point(1).bbox() + point(2).bbox(), t);
    }
    std::vector<std::pair<std::size_t, std::size_t>> candidates;
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(),
                                  [&](const Box& x, const Box& y) { candidates.emplace_back(std::min(x.info(), y.info()), std::max(x.info(), y.info())); });
    return candidates;
}

}  // namespace

CgalCrossings cgal_crossings(const Mesh& soup) {
    CgalCrossings result;
    for (const auto& [i, j] : box_pairs(soup, result.degenerate)) result.pairs += triangles_cross(soup, i, j);
    return result;
}

std::vector<std::pair<std::size_t, std::size_t>> cgal_crossing_pairs(const Mesh& soup) {
    std::size_t degenerate = 0;
    std::vector<std::pair<std::size_t, std::size_t>> crossing;
    for (const auto& [i, j] : box_pairs(soup, degenerate))
        if (triangles_cross(soup, i, j)) crossing.push_back({i, j});
    return crossing;
}

}  // namespace vdbmesh::test
