#pragma once
// A mesh of three components for the bounded measure's and section's tests (issue 28): a torus
// (test_meshes.h) and, apart from it, a box of side 4 with a cavity of side 1 (an inverted cube).

#include <utility>

#include "test_meshes.h"

namespace vdbmesh::test {

inline Mesh torus_and_box_with_cavity() {
    Mesh mesh = torus(40, 24);
    const auto append = [&](Mesh part, bool inverted) {
        const auto base = std::uint32_t(mesh.vertices.size());
        mesh.vertices.insert(mesh.vertices.end(), part.vertices.begin(), part.vertices.end());
        for (auto t : part.triangles) {
            if (inverted) std::swap(t[1], t[2]);
            mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
        }
    };
    append(cube({10, -2, -2}, 4), false);
    append(cube({11, -1, -1}, 1), true);
    return mesh;
}

}  // namespace vdbmesh::test
