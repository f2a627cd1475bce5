#pragma once
// How far a reconstructed surface is from a reference mesh, both ways (the bunny figures of
// issue 13, shared by tests/points and bench/points_bench.cpp). Distances are exact to the
// triangles (closest point through a BVH), in % of the reference's bounding-box diagonal.

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

#include "vdbmesh/geometry.h"
#include "vdbmesh/mesh.h"

namespace vdbmesh::test {

inline double box_diagonal(const Mesh& mesh) {
    std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const auto& v : mesh.vertices)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], double(v[a])), hi[a] = std::max(hi[a], double(v[a]));
    return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

inline detail::TriangleBvh bvh_of(const Mesh& mesh) {
    std::vector<std::uint32_t> all(mesh.triangles.size());
    std::iota(all.begin(), all.end(), 0u);
    return detail::TriangleBvh(mesh, std::move(all));
}

struct ReferenceToSurface {
    double max_percent = 0, mean_percent = 0;
};

/// Every vertex of @a reference to the surface @a mesh (the accuracy figure).
inline ReferenceToSurface reference_to_surface(const Mesh& reference, const Mesh& mesh) {
    const detail::TriangleBvh bvh = bvh_of(mesh);
    const double diagonal = box_diagonal(reference);
    double worst = 0, sum = 0;
    for (const auto& v : reference.vertices) {
        const double d = std::sqrt(bvh.closest_point(detail::Point3{v[0], v[1], v[2]}).distance_squared);
        worst = std::max(worst, d);
        sum += d;
    }
    return {100.0 * worst / diagonal, 100.0 * sum / double(std::max<std::size_t>(reference.vertices.size(), 1)) / diagonal};
}

struct SurfaceToReference {
    /// Over the vertices that are not across one of the reference's holes (where a hole's rim is
    /// about as near as its surface, the reference has no surface to compare with): the
    /// deepest inward (behind the reference's outward side) and farthest outward distances,
    /// the mean, the 99th percentile, and how many vertices lie beyond 0.5% of the diagonal.
    double inward_max_percent = 0, outward_max_percent = 0, mean_percent = 0, p99_percent = 0;
    std::size_t counted = 0, at_holes = 0, beyond_half_percent = 0;
    std::array<double, 3> deepest{0, 0, 0};  ///< the vertex of the deepest inward distance
};

/// The vertices of @a mesh to the surface of @a reference, signed by the reference's triangle
/// normals (outward when its signed volume about its centroid is positive, as bun_zipper's is).
inline SurfaceToReference surface_to_reference(const Mesh& mesh, const Mesh& reference) {
    const detail::TriangleBvh bvh = bvh_of(reference);
    const double diagonal = box_diagonal(reference);
    // The reference's boundary edges (used by one triangle): the rims of its holes.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const auto& t : reference.triangles)
        for (int k = 0; k < 3; ++k) ++uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
    auto point = [&](std::uint32_t i) {
        const auto& v = reference.vertices[i];
        return std::array<double, 3>{v[0], v[1], v[2]};
    };
    std::vector<std::array<std::array<double, 3>, 2>> rim;
    for (const auto& [edge, count] : uses)
        if (count == 1) rim.push_back({point(edge.first), point(edge.second)});
    auto rim_distance = [&](const detail::Point3& c) {
        double best = 1e300;
        for (const auto& [p, q] : rim) {
            double e2 = 0, along = 0;
            for (int d = 0; d < 3; ++d) e2 += (q[d] - p[d]) * (q[d] - p[d]), along += (c[d] - p[d]) * (q[d] - p[d]);
            const double s = std::clamp(along / std::max(e2, 1e-300), 0.0, 1.0);
            double off = 0;
            for (int d = 0; d < 3; ++d) off += (c[d] - p[d] - s * (q[d] - p[d])) * (c[d] - p[d] - s * (q[d] - p[d]));
            best = std::min(best, off);
        }
        return std::sqrt(best);
    };
    auto normal = [&](std::uint32_t triangle) {
        const auto& t = reference.triangles[triangle];
        const auto a = point(t[0]), b = point(t[1]), c = point(t[2]);
        const std::array<double, 3> u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        return std::array<double, 3>{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    };
    // Orientation: the sign of the signed volume about the centroid.
    std::array<double, 3> centroid{0, 0, 0};
    for (std::size_t i = 0; i < reference.vertices.size(); ++i)
        for (int d = 0; d < 3; ++d) centroid[d] += reference.vertices[i][d] / double(reference.vertices.size());
    double volume = 0;
    for (std::uint32_t t = 0; t < reference.triangles.size(); ++t) {
        const auto n = normal(t);
        const auto a = point(reference.triangles[t][0]);
        volume += n[0] * (a[0] - centroid[0]) + n[1] * (a[1] - centroid[1]) + n[2] * (a[2] - centroid[2]);
    }
    const double outward = volume >= 0 ? 1.0 : -1.0;
    SurfaceToReference r;
    std::vector<double> distances;
    double sum = 0;
    for (const auto& v : mesh.vertices) {
        const detail::Point3 p{v[0], v[1], v[2]};
        const detail::ClosestPoint c = bvh.closest_point(p);
        // Across a hole: the rim about as near as the surface (within twice its distance).
        // Only looked for beyond 0.1% (the rims are searched one edge after another).
        const double distance = std::sqrt(c.distance_squared);
        if (distance > 1e-3 * diagonal && rim_distance(p) <= 2 * distance) {
            ++r.at_holes;
            continue;
        }
        const auto n = normal(c.triangle);
        const double side = outward * ((p[0] - c.point[0]) * n[0] + (p[1] - c.point[1]) * n[1] + (p[2] - c.point[2]) * n[2]);
        const double d = 100.0 * std::sqrt(c.distance_squared) / diagonal;
        if (side < 0 && d > r.inward_max_percent) r.inward_max_percent = d, r.deepest = {v[0], v[1], v[2]};
        if (side >= 0) r.outward_max_percent = std::max(r.outward_max_percent, d);
        r.beyond_half_percent += d > 0.5;
        distances.push_back(d);
        sum += d;
    }
    r.counted = distances.size();
    if (!distances.empty()) {
        r.mean_percent = sum / double(distances.size());
        std::nth_element(distances.begin(), distances.begin() + long(distances.size() * 99 / 100), distances.end());
        r.p99_percent = distances[distances.size() * 99 / 100];
    }
    return r;
}

}  // namespace vdbmesh::test
