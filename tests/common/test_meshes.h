#pragma once
// Tiny hand-made meshes with known answers, for the analysis tests.

#include <cmath>

#include "vdbmesh/mesh.h"

namespace vdbmesh::test {

/// The unit right tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1), outward.
inline Mesh tetrahedron() {
    return {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
}

/// The axis-aligned box from @a lo with edge @a side, 8 vertices (index x + 2y + 4z), 12 outward triangles.
inline Mesh cube(std::array<float, 3> lo = {0, 0, 0}, float side = 1) {
    Mesh mesh;
    for (int i = 0; i < 8; ++i) {
        mesh.vertices.push_back({lo[0] + side * float(i & 1), lo[1] + side * float((i >> 1) & 1),
                                 lo[2] + side * float((i >> 2) & 1)});
    }
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        mesh.triangles.push_back({q[0], q[1], q[2]});
        mesh.triangles.push_back({q[0], q[2], q[3]});
    }
    return mesh;
}

/// A torus about the z axis (ring radius @a ring, tube radius @a tube) as an n x m grid of quads.
/// The box [0, 1] x [0, 2] x [0, 3] (cube() stretched): 8 vertices, 12 outward triangles.
inline Mesh box_123() {
    Mesh mesh = cube();
    for (auto& v : mesh.vertices) v = {v[0], 2 * v[1], 3 * v[2]};
    return mesh;
}

inline Mesh torus(int n = 16, int m = 8, double ring = 3, double tube = 1) {
    const double pi = 3.14159265358979323846;
    Mesh mesh;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < m; ++j) {
            const double u = 2 * pi * i / n, v = 2 * pi * j / m;
            mesh.vertices.push_back({float((ring + tube * std::cos(v)) * std::cos(u)),
                                     float((ring + tube * std::cos(v)) * std::sin(u)), float(tube * std::sin(v))});
        }
    }
    const auto id = [&](int i, int j) { return std::uint32_t((i % n) * m + (j % m)); };
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < m; ++j) {
            mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    }
    return mesh;
}

/// A mesh of loose triangles given by their corners (no shared indices).
inline Mesh triangle_soup(const std::vector<std::array<std::array<float, 3>, 3>>& triangles) {
    Mesh mesh;
    for (const auto& t : triangles) {
        const auto base = std::uint32_t(mesh.vertices.size());
        for (const auto& p : t) mesh.vertices.push_back(p);
        mesh.triangles.push_back({base, base + 1, base + 2});
    }
    return mesh;
}

}  // namespace vdbmesh::test
