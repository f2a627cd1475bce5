#pragma once
// Small checks on meshes and analytic test grids for the mesher tests (until the validator of
// analysis.h lands): edge topology, degeneracies, signed volume.

#include <openvdb/openvdb.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <algorithm>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include "vdbmesh/mesh.h"

namespace vdbmesh::test {

struct EdgeCounts {
    std::size_t boundary = 0;     ///< undirected edges used by one triangle
    std::size_t nonmanifold = 0;  ///< used by more than two
    std::size_t misoriented = 0;  ///< a directed edge used more than once
};

inline EdgeCounts count_edges(const Mesh& mesh) {
    // Directed edges as 64-bit keys (from << 32 | to), sorted: runs give the use counts.
    std::vector<std::uint64_t> directed;
    directed.reserve(3 * mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        for (int i = 0; i < 3; ++i) directed.push_back(std::uint64_t(t[i]) << 32 | t[(i + 1) % 3]);
    }
    std::sort(directed.begin(), directed.end());
    auto uses = [&](std::uint64_t key) {
        const auto range = std::equal_range(directed.begin(), directed.end(), key);
        return std::size_t(range.second - range.first);
    };
    EdgeCounts counts;
    for (std::size_t i = 0; i < directed.size();) {
        const std::uint64_t key = directed[i];
        const std::size_t n = uses(key);
        i += n;
        if (n > 1) ++counts.misoriented;
        const std::uint64_t reverse_key = (key << 32) | (key >> 32);
        const std::size_t reverse = uses(reverse_key);
        if (reverse != 0 && reverse_key < key) continue;  // counted with its reverse
        if (n + reverse == 1) ++counts.boundary;
        if (n + reverse > 2) ++counts.nonmanifold;
    }
    return counts;
}

inline std::array<double, 3> position(const Mesh& mesh, std::uint32_t v) {
    return {mesh.vertices[v][0], mesh.vertices[v][1], mesh.vertices[v][2]};
}

inline std::array<double, 3> cross_of_edges(const Mesh& mesh, const std::array<std::uint32_t, 3>& t) {
    const auto a = position(mesh, t[0]), b = position(mesh, t[1]), c = position(mesh, t[2]);
    const std::array<double, 3> u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}

/// Triangles with a repeated vertex index or exactly collinear corners.
inline std::size_t degenerate_triangles(const Mesh& mesh) {
    std::size_t n = 0;
    for (const auto& t : mesh.triangles) {
        const auto c = cross_of_edges(mesh, t);
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || (c[0] == 0 && c[1] == 0 && c[2] == 0)) ++n;
    }
    return n;
}

/// Vertices whose coordinates equal those of another vertex.
inline std::size_t coincident_vertices(const Mesh& mesh) {
    std::set<std::array<float, 3>> seen(mesh.vertices.begin(), mesh.vertices.end());
    return mesh.vertices.size() - seen.size();
}

/// Signed volume by the divergence theorem: positive when a closed mesh's normals point out.
inline double signed_volume(const Mesh& mesh) {
    double volume = 0;
    for (const auto& t : mesh.triangles) {
        const auto a = position(mesh, t[0]), b = position(mesh, t[1]), c = position(mesh, t[2]);
        volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                   a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
    }
    return volume;
}

inline double surface_area(const Mesh& mesh) {
    double area = 0;
    for (const auto& t : mesh.triangles) {
        const auto c = cross_of_edges(mesh, t);
        area += 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    }
    return area;
}

/// A grid holding field(i, j, k) as active voxels over @a box, @a background elsewhere.
inline openvdb::FloatGrid::Ptr make_grid(const openvdb::CoordBBox& box, const std::function<float(int, int, int)>& field,
                                         float background) {
    auto grid = openvdb::FloatGrid::create(background);
    auto accessor = grid->getAccessor();
    for (auto it = box.begin(); it; ++it) accessor.setValue(*it, field((*it).x(), (*it).y(), (*it).z()));
    return grid;
}

/// Density of a ball: radius - distance to @a centre (positive inside, a signed distance).
inline openvdb::FloatGrid::Ptr make_ball(double radius, const std::array<double, 3>& centre) {
    const int reach = int(std::ceil(radius)) + 3;
    const openvdb::CoordBBox box(openvdb::Coord(int(centre[0]) - reach, int(centre[1]) - reach, int(centre[2]) - reach),
                                 openvdb::Coord(int(centre[0]) + reach, int(centre[1]) + reach, int(centre[2]) + reach));
    return make_grid(box, [&](int i, int j, int k) {
        const double dx = i - centre[0], dy = j - centre[1], dz = k - centre[2];
        return float(radius - std::sqrt(dx * dx + dy * dy + dz * dz));
    }, -float(reach));
}

}  // namespace vdbmesh::test
