#pragma once
// A mesh of three components for the bounded measure's and section's tests (issue 28): a torus
// (test_meshes.h) and, apart from it, a box of side 4 with a cavity of side 1 (an inverted cube);
// and that mesh written in every format the streams read.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "test_meshes.h"
#include "vdbmesh/mesh_io.h"

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

/// torus_and_box_with_cavity() written into @a dir as binary and ASCII PLY, STL and OBJ: the six
/// files, named by encoding and extension ("binary.ply" ...).
inline std::vector<std::filesystem::path> solids_in_every_format(const std::filesystem::path& dir) {
    std::vector<std::filesystem::path> files;
    for (const bool ascii : {false, true}) {
        for (const char* extension : {".ply", ".stl", ".obj"}) {
            files.push_back(dir / (std::string(ascii ? "ascii" : "binary") + extension));
            write_mesh(torus_and_box_with_cavity(), files.back(), {ascii, false});
        }
    }
    return files;
}

}  // namespace vdbmesh::test
