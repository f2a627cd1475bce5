// The closed pieces of each label's mesh and their signed volumes (label_components.h).

#include "labels/label_components.h"

#include <tbb/parallel_sort.h>

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
    std::vector<std::pair<std::uint64_t, std::uint32_t>> uses;  // (vertex << 16 | label, half-triangle)
    uses.reserve(6 * mesh.triangles.size());
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
        for (int side = 0; side < 2; ++side)
            if (sides[t][side] != 0)
                for (std::uint32_t v : mesh.triangles[t]) uses.push_back({std::uint64_t(v) << 16 | sides[t][side], 2 * t + side});
    tbb::parallel_sort(uses.begin(), uses.end());  // the pairs are distinct: the same order for any thread count
    for (std::size_t i = 1; i < uses.size(); ++i)
        if (uses[i].first == uses[i - 1].first) parent[find(parent, uses[i].second)] = find(parent, uses[i - 1].second);
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
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const double v = tet_volume(mesh, mesh.triangles[t], origin);
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
