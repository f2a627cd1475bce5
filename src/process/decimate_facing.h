#pragma once
// Private to the decimator (decimate_*.cpp): the 32 directions its intersection proof tries,
// which of them a triangle certainly faces (a table over its normal), and what a set of
// triangles has in common.

#include <array>
#include <cmath>
#include <cstdint>

#include "process/decimate_geometry.h"

namespace vdbmesh::detail::decimation {

/// What the triangles in a part of space have in common: the directions they all face and the
/// component they all belong to (kNone: no triangle; kMixed: more than one).
struct Summary {
    static constexpr std::uint32_t kMixed = kNone - 1;
    std::uint32_t facing = ~0u;  ///< bit k: direction k of kDirections
    std::uint32_t component = kNone;
    void add(const Summary& o) {
        facing &= o.facing;
        component = component == kNone ? o.component : o.component == kNone || o.component == component ? component : kMixed;
    }
    /// Whether triangles with this in common clear a collapse (intersection_free()'s proof):
    /// they all face a common direction, in one component.
    bool clears() const { return component != kMixed && facing != 0; }
};

/// 32 directions spread evenly over the sphere (a golden-angle spiral).
inline const std::array<Vec3d, 32> kDirections = [] {
    std::array<Vec3d, 32> directions{};
    for (std::size_t k = 0; k < directions.size(); ++k) {
        const double z = 1 - (2 * double(k) + 1) / double(directions.size()), r = std::sqrt(1 - z * z), phi = double(k) * 2.399963229728653;
        directions[k] = {r * std::cos(phi), r * std::sin(phi), z};
    }
    return directions;
}();

/// The directions of kDirections that every normal in a part of the sphere faces, for normals
/// binned by the cube face their largest component points to and a kBins x kBins square there.
class FacingTable {
public:
    static constexpr int kBins = 16;

    FacingTable() {
        for (int face = 0; face < 6; ++face) {
            for (int i = 0; i < kBins; ++i) {
                for (int j = 0; j < kBins; ++j) table_[(face * kBins + i) * kBins + j] = facing_all(face, i, j);
            }
        }
    }

    /// The directions that @a n certainly faces (the triangle's normal, from edges whose
    /// squared lengths multiply to @a scale_squared): none when it is so short that its rounding
    /// (2^-49 times the edges' lengths at most) could turn it by more than 1e-6.
    std::uint32_t facing(const Vec3d& n, double scale_squared) const {
        const double m[3] = {std::abs(n[0]), std::abs(n[1]), std::abs(n[2])};
        const int axis = m[0] >= m[1] && m[0] >= m[2] ? 0 : m[1] >= m[2] ? 1 : 2;
        if (!(m[axis] * m[axis] > 1e-12 * scale_squared)) return 0;
        const int face = 2 * axis + (n[axis] < 0);
        const double inverse = 1 / m[axis];
        return table_[(face * kBins + bin(n[(axis + 1) % 3] * inverse)) * kBins + bin(n[(axis + 2) % 3] * inverse)];
    }

private:
    static int bin(double t) { return std::clamp(int(std::floor((t + 1) / 2 * kBins)), 0, kBins - 1); }

    /// The directions faced by every ray through the square (i, j) of @a face, and by rays
    /// within 1e-6 of it: the dot product is linear over the square, least at a corner.
    static std::uint32_t facing_all(int face, int i, int j) {
        const int axis = face / 2;
        const double sign = face % 2 ? -1 : 1;
        std::uint32_t facing = ~0u;
        for (const int di : {0, 1}) {
            for (const int dj : {0, 1}) {
                Vec3d corner{};
                corner[std::size_t(axis)] = sign;
                corner[std::size_t((axis + 1) % 3)] = -1 + 2.0 * (i + di) / kBins;
                corner[std::size_t((axis + 2) % 3)] = -1 + 2.0 * (j + dj) / kBins;
                const double length = std::sqrt(dot(corner, corner));
                std::uint32_t faced = 0;
                for (std::size_t k = 0; k < kDirections.size(); ++k) {
                    if (dot(kDirections[k], corner) > 1e-5 * length) faced |= 1u << k;
                }
                facing &= faced;
            }
        }
        return facing;
    }

    std::array<std::uint32_t, 6 * kBins * kBins> table_;
};

inline const FacingTable kFacingTable;

/// The directions of kDirections that triangle @a t certainly faces (its normal's dot product
/// with them is positive); none for a degenerate one.
inline std::uint32_t facing_directions(const detail::Triangle3& t) {
    const Vec3d e1 = sub(t[1], t[0]), e2 = sub(t[2], t[0]);
    return kFacingTable.facing(cross(e1, e2), dot(e1, e1) * dot(e2, e2));
}


}  // namespace vdbmesh::detail::decimation
