// analyze_mesh(): the validator behind `vdbmesh check` (DESIGN.md section 6). It gathers the
// topology (topology.cpp), degenerate faces (classify_faces.cpp), exact self-intersections
// (find_self_intersections.cpp), integrals (integrals.cpp), per-component orientation and
// the angle quality of the regular triangles.
#include <algorithm>
#include <cmath>
#include <limits>

#include "analysis/block_reduce.h"
#include "analysis/report_parts.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/analysis.h"

namespace vdbmesh {
namespace {

/// The angles of the listed triangles; flagged: those under kSmallAngleDeg.
detail::ValueStats angle_stats(const Mesh& mesh, const std::vector<std::uint32_t>& regular) {
    return detail::block_stats(regular.size(), 16384, [&](std::size_t i, detail::ValueStats& stats) {
        const auto& t = mesh.triangles[regular[i]];
        for (const double angle : detail::triangle_angles(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]])) {
            stats.add(angle, angle < detail::kSmallAngleDeg);
        }
    });
}

/// Number of components whose signed volume is negative. Each component's tetrahedra join
/// its triangles to its first vertex, which keeps far-away components well conditioned.
std::size_t count_negative_components(const Mesh& mesh, const detail::Topology& topology) {
    std::vector<double> volume(topology.components, 0.0);
    std::vector<std::array<double, 3>> reference;
    reference.reserve(topology.components);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const auto& t = mesh.triangles[i];
        const std::uint32_t component = topology.component_of_triangle[i];
        if (component == reference.size()) {  // numbered in order of first appearance
            const auto& v = mesh.vertices[t[0]];
            reference.push_back({v[0], v[1], v[2]});
        }
        const auto& r = reference[component];
        const auto corner = [&](int k) {
            const auto& v = mesh.vertices[t[k]];
            return std::array<double, 3>{v[0] - r[0], v[1] - r[1], v[2] - r[2]};
        };
        const auto a = corner(0), b = corner(1), c = corner(2);
        volume[component] += a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                             a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    return std::size_t(std::count_if(volume.begin(), volume.end(), [](double v) { return v < 0; }));
}

}  // namespace

namespace detail {

std::array<double, 3> triangle_angles(const std::array<float, 3>& a, const std::array<float, 3>& b, const std::array<float, 3>& c) {
    constexpr double kPi = 3.14159265358979323846;
    const std::array<const std::array<float, 3>*, 3> p{&a, &b, &c};
    std::array<double, 3> angles{};
    for (int k = 0; k < 3; ++k) {
        const auto& o = *p[k];
        const auto& u = *p[(k + 1) % 3];
        const auto& w = *p[(k + 2) % 3];
        const double e1[3] = {double(u[0]) - o[0], double(u[1]) - o[1], double(u[2]) - o[2]};
        const double e2[3] = {double(w[0]) - o[0], double(w[1]) - o[1], double(w[2]) - o[2]};
        const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                     cz = e1[0] * e2[1] - e1[1] * e2[0];
        const double sine = std::sqrt(cx * cx + cy * cy + cz * cz);
        const double cosine = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
        angles[k] = std::atan2(sine, cosine) * 180.0 / kPi;
    }
    return angles;
}

void add_topology(const Topology& topology, MeshAnalysis& report) {
    report.unreferenced_vertices = report.vertices - topology.referenced_vertices;
    report.edges = topology.edges;
    report.boundary_edges = topology.boundary_edges;
    report.boundary_loops = topology.boundary_loops;
    report.nonmanifold_edges = topology.nonmanifold_edges;
    report.nonmanifold_vertices = topology.nonmanifold_vertices;
    report.misoriented_edges = topology.misoriented_edges;
    report.components = topology.components;
    report.euler_characteristic =
        (long long)topology.referenced_vertices - (long long)topology.edges + (long long)report.triangles;
    if (topology.nonmanifold_edges == 0 && topology.nonmanifold_vertices == 0) {
        report.genus = (2 * (long long)topology.components - report.euler_characteristic -
                        (long long)topology.boundary_loops) / 2;
    }
    report.closed = report.triangles > 0 && topology.boundary_edges == 0;
}

void add_faces(const std::array<std::size_t, 3>& class_counts, const ValueStats& angles, MeshAnalysis& report) {
    report.repeated_vertex_faces = class_counts[std::size_t(FaceClass::kRepeatedVertex)];
    report.zero_area_faces = class_counts[std::size_t(FaceClass::kZeroArea)];
    report.degenerate_faces = report.repeated_vertex_faces + report.zero_area_faces;
    if (angles.count > 0) {
        report.min_angle_deg = angles.min;
        report.small_angle_share = double(angles.flagged) / double(angles.count);
    }
}

void add_integrals(const MeshIntegrals& integrals, MeshAnalysis& report) {
    report.area = integrals.area;
    report.volume = integrals.volume;
    report.centroid = integrals.centroid;
    report.inertia = integrals.inertia;
    report.outward = integrals.volume > 0;
}

}  // namespace detail

bool MeshAnalysis::is_clean() const {
    return triangles > 0 && closed && nonmanifold_edges == 0 && nonmanifold_vertices == 0 &&
           misoriented_edges == 0 && outward && self_intersecting_pairs == 0 && degenerate_faces == 0;
}

MeshAnalysis analyze_mesh(const Mesh& mesh) {
    detail::check_indices(mesh);
    MeshAnalysis report;
    report.triangles = mesh.triangles.size();
    report.vertices = mesh.vertices.size();

    const detail::Topology topology = detail::analyze_topology(mesh);
    detail::add_topology(topology, report);

    const std::vector<detail::FaceClass> classes = detail::classify_faces(mesh);
    std::array<std::size_t, 3> class_counts{};
    for (const detail::FaceClass c : classes) ++class_counts[std::size_t(c)];
    detail::add_faces(class_counts, angle_stats(mesh, detail::regular_faces(classes)), report);
    report.self_intersecting_pairs = find_self_intersections(mesh).size();

    detail::add_integrals(mesh_integrals(mesh), report);
    report.negative_components = count_negative_components(mesh, topology);
    return report;
}

}  // namespace vdbmesh
