// Normals for the writers: facet normals for STL, and per-vertex normals as the area-weighted
// average of the incident facet normals (the sum of unnormalized cross products), for PLY/OBJ.
#include <cmath>

#include "io/mesh_io_detail.h"

namespace vdbmesh::detail {
namespace {

std::array<double, 3> cross_product(const Corners& corners) {
    const auto& [a, b, c] = corners;
    const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
    const double w[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    return {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
}

std::array<double, 3> cross_product(const Mesh& mesh, const std::array<std::uint32_t, 3>& t) {
    return cross_product(Corners{mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]});
}

std::array<float, 3> normalized(const std::array<double, 3>& v) {
    const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(length > 0)) return {0, 0, 0};
    return {float(v[0] / length), float(v[1] / length), float(v[2] / length)};
}

}  // namespace

std::array<float, 3> facet_normal(const Corners& corners) { return normalized(cross_product(corners)); }

std::vector<std::array<float, 3>> vertex_normals(const Mesh& mesh) {
    std::vector<std::array<double, 3>> sums(mesh.vertices.size(), {0, 0, 0});
    for (const auto& t : mesh.triangles) {
        const std::array<double, 3> n = cross_product(mesh, t);  // length = twice the area
        for (const std::uint32_t v : t) {
            for (int k = 0; k < 3; ++k) sums[v][k] += n[k];
        }
    }
    std::vector<std::array<float, 3>> normals(mesh.vertices.size());
    for (std::size_t v = 0; v < sums.size(); ++v) normals[v] = normalized(sums[v]);
    return normals;
}

}  // namespace vdbmesh::detail
