// The closed pieces of each label's mesh and their signed volumes (label_components.h).

#include "labels/label_components.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>

namespace vdbmesh::labels_detail {
namespace {

std::uint32_t find(std::vector<std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

/// Signed volume of the tetrahedron (origin, a, b, c), relative to @a origin for accuracy.
double tet_volume(const Mesh& mesh, const std::array<std::uint32_t, 3>& t, const std::array<float, 3>& origin) {
    std::array<std::array<double, 3>, 3> p;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) p[i][k] = double(mesh.vertices[t[i]][k]) - origin[k];
    return (p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) - p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
            p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0])) / 6;
}

}  // namespace

LabelComponents::LabelComponents(const Mesh& mesh, const std::vector<std::array<std::uint16_t, 2>>& sides) {
    // Half-triangle h = 2 t + side; half-triangles of one label that share a vertex are one piece.
    std::vector<std::uint32_t> parent(2 * mesh.triangles.size());
    std::iota(parent.begin(), parent.end(), 0u);
    std::vector<std::uint32_t> start(mesh.vertices.size() + 1, 0), round;  // per vertex its triangles (compressed rows)
    for (const auto& tri : mesh.triangles)
        for (std::uint32_t v : tri) ++start[v + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    round.resize(start.back());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
        for (std::uint32_t v : mesh.triangles[t]) round[fill[v]++] = t;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        for (std::uint32_t i = start[v]; i < start[v + 1]; ++i)
            for (int side = 0; side < 2; ++side) {
                const std::uint16_t label = sides[round[i]][side];
                if (label == 0) continue;
                // Joined to the first half-triangle of the same label round the vertex.
                for (std::uint32_t j = start[v]; j <= i; ++j) {
                    const int other = sides[round[j]][0] == label ? 0 : sides[round[j]][1] == label ? 1 : -1;
                    if (other < 0) continue;
                    parent[find(parent, 2 * round[i] + std::uint32_t(side))] = find(parent, 2 * round[j] + std::uint32_t(other));
                    break;
                }
            }
    std::vector<std::int32_t> number(parent.size(), -1);
    piece_.assign(mesh.triangles.size(), {-1, -1});
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
        for (int side = 0; side < 2; ++side) {
            if (sides[t][side] == 0) continue;
            std::int32_t& n = number[find(parent, 2 * t + side)];
            if (n < 0) n = std::int32_t(pieces_++);
            piece_[t][side] = n;
        }
}

std::vector<double> LabelComponents::volumes(const Mesh& mesh) const {
    std::vector<double> volume(pieces_, 0.0);
    const std::array<float, 3> origin = mesh.vertices.empty() ? std::array<float, 3>{0, 0, 0} : mesh.vertices.front();
    // Each triangle's share in parallel, summed per piece in triangle order (the same sums for any thread count).
    std::vector<double> share(mesh.triangles.size());
    tbb::parallel_for(std::size_t(0), share.size(), [&](std::size_t t) { share[t] = tet_volume(mesh, mesh.triangles[t], origin); });
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const double v = share[t];
        if (piece_[t][0] >= 0) volume[std::size_t(piece_[t][0])] += v;
        if (piece_[t][1] >= 0) volume[std::size_t(piece_[t][1])] -= v;
    }
    return volume;
}

std::vector<std::uint8_t> LabelComponents::inverted(const Mesh& mesh, const std::vector<double>& reference) const {
    const std::vector<double> now = volumes(mesh);
    std::vector<std::uint8_t> flipped(pieces_, 0);
    for (std::size_t p = 0; p < pieces_; ++p) flipped[p] = !(now[p] * reference[p] > 0);
    std::vector<std::uint8_t> bad(mesh.vertices.size(), 0);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int side = 0; side < 2; ++side)
            if (piece_[t][side] >= 0 && flipped[std::size_t(piece_[t][side])])
                for (std::uint32_t v : mesh.triangles[t]) bad[v] = 1;
    return bad;
}

}  // namespace vdbmesh::labels_detail
