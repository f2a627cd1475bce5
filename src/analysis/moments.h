#pragma once
// Private: the sums behind mesh_integrals() (integrals.cpp), shared with the bounded check
// (analyze_stream.cpp), which adds the same triangles in the same blocks for the same bits.

#include <array>
#include <cmath>
#include <cstddef>

#include "vdbmesh/analysis.h"

namespace vdbmesh::detail {

using Vec = std::array<double, 3>;
using Mat = std::array<Vec, 3>;

/// Triangles are summed in blocks of this many, each block from zero, the blocks in order.
constexpr std::size_t kMomentsBlock = 16384;

struct Moments {
    double area = 0, volume = 0;
    Vec first{};        ///< int (x - r) dV
    Mat second{};       ///< int (x - r)(x - r)^T dV
    Vec surface_first{};  ///< int (x - r) dA, for the centroid of a surface without volume

    void add(const Moments& o) {
        area += o.area, volume += o.volume;
        for (int i = 0; i < 3; ++i) {
            first[i] += o.first[i], surface_first[i] += o.surface_first[i];
            for (int j = 0; j < 3; ++j) second[i][j] += o.second[i][j];
        }
    }
};

inline Vec cross(const Vec& a, const Vec& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
inline double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

inline void add_triangle(const Vec& a, const Vec& b, const Vec& c, Moments& m) {
    const Vec ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ac{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const Vec n = cross(ab, ac);
    const double area = 0.5 * std::sqrt(dot(n, n));
    const double det = dot(a, cross(b, c));
    const Vec s{a[0] + b[0] + c[0], a[1] + b[1] + c[1], a[2] + b[2] + c[2]};
    m.area += area;
    m.volume += det / 6;
    for (int i = 0; i < 3; ++i) {
        m.first[i] += det / 24 * s[i];
        m.surface_first[i] += area / 3 * s[i];
        for (int j = 0; j < 3; ++j) m.second[i][j] += det / 120 * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
    }
}

/// The integrals from the sums of the triangles' corners taken about @a r.
MeshIntegrals integrals_from(const Moments& m, const Vec& r);

}  // namespace vdbmesh::detail
