#pragma once
// Helpers of the process tests: phantom meshes and how far a mesh lies from the exact surface.

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "phantom_grid.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/phantom.h"

namespace vdbmesh::test {

inline constexpr double kPi = 3.14159265358979323846;

/// The phantom meshed like a scan (DC at error 0, iso 0.5).
inline Mesh phantom_mesh(const PhantomSpec& spec) {
    MeshOptions options;
    options.iso = 0.5;
    return mesh_grid(*phantom_scan_grid(spec), options).mesh;
}

/// Root mean square of the vertices' exact distance to the phantom's surface (voxels).
inline double rms_distance(const Mesh& mesh, const PhantomSpec& spec) {
    double sum = 0;
    for (const auto& v : mesh.vertices) {
        const double d = phantom_signed_distance(spec, v[0], v[1], v[2]);
        sum += d * d;
    }
    return std::sqrt(sum / double(mesh.vertices.size()));
}

/// Roughness: the root mean square angle (radians) between the normals of the two triangles
/// on each edge. About 0.05 on a smooth sphere of radius 20 voxels meshed at one voxel; noise raises it.
inline double rms_dihedral(const Mesh& mesh) {
    const auto normal = [&](const std::array<std::uint32_t, 3>& t) {
        const auto& a = mesh.vertices[t[0]];
        const auto& b = mesh.vertices[t[1]];
        const auto& c = mesh.vertices[t[2]];
        const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
        const double v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
        std::array<double, 3> n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (double& x : n) x /= length;
        return n;
    };
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::array<double, 3>> first_normal;
    double sum = 0;
    std::size_t edges = 0;
    for (const auto& t : mesh.triangles) {
        const std::array<double, 3> n = normal(t);
        for (int k = 0; k < 3; ++k) {
            const auto key = std::minmax(t[k], t[(k + 1) % 3]);
            const auto found = first_normal.find(key);
            if (found == first_normal.end()) {
                first_normal.emplace(key, n);
                continue;
            }
            const auto& m = found->second;
            const double cosine = std::clamp(n[0] * m[0] + n[1] * m[1] + n[2] * m[2], -1.0, 1.0);
            sum += std::acos(cosine) * std::acos(cosine);
            ++edges;
        }
    }
    return std::sqrt(sum / double(edges));
}

}  // namespace vdbmesh::test
