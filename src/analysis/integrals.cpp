// Area, volume, centroid and inertia of the solid bounded by a triangle mesh. The volume
// integrals of g in {1, x, y, z, x^2, y^2, z^2, xy, yz, zx} are turned into surface integrals
// by the divergence theorem, as in A. A. Kononykhin's thesis (shared seed 002, chapter 3.3,
// where the surface is an RBF model). On a triangle mesh the surface sum is exact: it is the
// sum over the signed tetrahedra (r, a, b, c) joining a reference point r to each triangle, with
//   V = det/6,  int x = V (a + b + c)/4,  int x_i x_j = V/20 (sum_k p_ki p_kj + s_i s_j)
// (p_k the corners with r = 0, s their sum). r is a mesh vertex, which keeps the sums small.
#include <cmath>

#include "analysis/block_reduce.h"
#include "analysis/moments.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/analysis.h"

namespace vdbmesh {

MeshIntegrals mesh_integrals(const Mesh& mesh) {
    detail::check_indices(mesh);
    MeshIntegrals result;
    if (mesh.triangles.empty()) return result;
    const auto& origin = mesh.vertices[mesh.triangles[0][0]];
    const detail::Vec r{origin[0], origin[1], origin[2]};
    const auto corner = [&](std::uint32_t v) {
        const auto& p = mesh.vertices[v];
        return detail::Vec{p[0] - r[0], p[1] - r[1], p[2] - r[2]};
    };
    const detail::Moments m = detail::block_reduce(
        mesh.triangles.size(), detail::kMomentsBlock, detail::Moments{},
        [&](std::size_t begin, std::size_t end) {
            detail::Moments local;
            for (std::size_t i = begin; i < end; ++i) {
                const auto& t = mesh.triangles[i];
                detail::add_triangle(corner(t[0]), corner(t[1]), corner(t[2]), local);
            }
            return local;
        },
        [](detail::Moments& total, const detail::Moments& block) { total.add(block); });
    return detail::integrals_from(m, r);
}

namespace detail {

MeshIntegrals integrals_from(const Moments& m, const Vec& r) {
    MeshIntegrals result;
    result.area = m.area;
    result.volume = m.volume;
    Vec offset{};  // centroid - r
    if (m.volume != 0) {
        for (int i = 0; i < 3; ++i) offset[i] = m.first[i] / m.volume;
    } else if (m.area > 0) {
        for (int i = 0; i < 3; ++i) offset[i] = m.surface_first[i] / m.area;
    }
    for (int i = 0; i < 3; ++i) result.centroid[i] = r[i] + offset[i];
    if (m.volume == 0) return result;
    // Second moments about the centroid, then I = trace(C) Id - C.
    Mat central{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) central[i][j] = m.second[i][j] - m.volume * offset[i] * offset[j];
    }
    const double trace = central[0][0] + central[1][1] + central[2][2];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) result.inertia[i][j] = (i == j ? trace : 0.0) - central[i][j];
    }
    return result;
}

}  // namespace detail
}  // namespace vdbmesh
