// CGAL's Poisson surface reconstruction (Kazhdan et al. 2006, CGAL's implementation) as the
// anchor of vdbmesh_points_bench: only this translation unit compiles CGAL.

#include "poisson_anchor.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/poisson_surface_reconstruction.h>

#include <utility>
#include <vector>

namespace vdbmesh::bench {

Mesh cgal_poisson(const PointCloud& cloud, double spacing_scale) {
    using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
    using Point = Kernel::Point_3;
    using Vector = Kernel::Vector_3;
    using Pwn = std::pair<Point, Vector>;
    std::vector<Pwn> points;
    points.reserve(cloud.points.size());
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        const auto& p = cloud.points[i];
        const auto& n = cloud.normals[i];
        points.emplace_back(Point(p[0], p[1], p[2]), Vector(n[0], n[1], n[2]));
    }
    const double spacing = CGAL::compute_average_spacing<CGAL::Sequential_tag>(
        points, 6, CGAL::parameters::point_map(CGAL::First_of_pair_property_map<Pwn>()));
    CGAL::Surface_mesh<Point> surface;
    CGAL::poisson_surface_reconstruction_delaunay(points.begin(), points.end(), CGAL::First_of_pair_property_map<Pwn>(),
                                                  CGAL::Second_of_pair_property_map<Pwn>(), surface, spacing * spacing_scale);
    Mesh mesh;
    std::vector<std::uint32_t> index(surface.number_of_vertices() + surface.number_of_removed_vertices());
    for (auto v : surface.vertices()) {
        index[v.idx()] = std::uint32_t(mesh.vertices.size());
        const Point& p = surface.point(v);
        mesh.vertices.push_back({float(p.x()), float(p.y()), float(p.z())});
    }
    for (auto f : surface.faces()) {
        std::array<std::uint32_t, 3> t{};
        int k = 0;
        for (auto v : CGAL::vertices_around_face(surface.halfedge(f), surface)) {
            if (k < 3) t[std::size_t(k)] = index[v.idx()];
            ++k;
        }
        if (k == 3) mesh.triangles.push_back(t);
    }
    return mesh;
}

}  // namespace vdbmesh::bench
