#pragma once
// The label map as the mesher reads it (private to src/labels): labels outside the map and
// labels not asked for are the background 0; voxel corners numbered over the padded box.

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "labels/corner_sheets.h"

namespace vdbmesh::labels_detail {

struct LabelGrid {
    std::array<std::int64_t, 3> dims{};  ///< voxels along x, y, z
    std::vector<std::uint16_t> labels;   ///< x fastest; unselected labels already 0
    std::vector<std::uint8_t> meshed;    ///< per label value 0..65535: 1 when it is meshed (not background)

    std::uint16_t at(std::int64_t x, std::int64_t y, std::int64_t z) const {
        if (x < 0 || y < 0 || z < 0 || x >= dims[0] || y >= dims[1] || z >= dims[2]) return 0;
        return labels[std::size_t((z * dims[1] + y) * dims[0] + x)];
    }
    /// Corner (a, b, c) lies between voxels a-1 and a along x (and so on): 0..dims inclusive.
    std::array<std::int64_t, 3> corner_dims() const { return {dims[0] + 1, dims[1] + 1, dims[2] + 1}; }
    std::size_t corner_index(std::int64_t a, std::int64_t b, std::int64_t c) const {
        return std::size_t((c * (dims[1] + 1) + b) * (dims[0] + 1) + a);
    }
    CornerLabels corner_labels(std::int64_t a, std::int64_t b, std::int64_t c) const {
        CornerLabels l;
        if (a > 0 && b > 0 && c > 0 && a < dims[0] && b < dims[1] && c < dims[2]) {  // inside: no bounds to check
            const std::size_t row = std::size_t(dims[0]), slice = row * std::size_t(dims[1]);
            const std::uint16_t* p = labels.data() + std::size_t(((c - 1) * dims[1] + b - 1) * dims[0] + a - 1);
            l = {p[0], p[1], p[row], p[row + 1], p[slice], p[slice + 1], p[slice + row], p[slice + row + 1]};
            return l;
        }
        for (int o = 0; o < 8; ++o) l[o] = at(a - 1 + (o & 1), b - 1 + (o >> 1 & 1), c - 1 + (o >> 2 & 1));
        return l;
    }
    /// The block round the corner and the voxels beyond each edge's far end (corner_sheets.h).
    CornerNeighbourhood neighbourhood(std::int64_t a, std::int64_t b, std::int64_t c) const {
        CornerNeighbourhood n;
        n.block = corner_labels(a, b, c);
        for (int axis = 0; axis < 3; ++axis)
            for (int side = 0; side < 2; ++side)
                for (int o = 0; o < 8; ++o) {
                    if ((o >> axis & 1) != side) continue;
                    std::array<std::int64_t, 3> voxel{a - 1 + (o & 1), b - 1 + (o >> 1 & 1), c - 1 + (o >> 2 & 1)};
                    voxel[axis] += side ? 1 : -1;
                    n.far[2 * axis + side][far_index(axis, o)] = at(voxel[0], voxel[1], voxel[2]);
                }
        return n;
    }
    /// Whether at most two labels meet at the corner (most corners: no sort).
    bool at_most_two_labels(std::int64_t a, std::int64_t b, std::int64_t c) const {
        const CornerLabels l = corner_labels(a, b, c);
        const auto other = std::find_if(l.begin(), l.end(), [&](std::uint16_t v) { return v != l[0]; });
        return std::all_of(other, l.end(), [&](std::uint16_t v) { return v == l[0] || v == *other; });
    }
    bool uniform(std::int64_t a, std::int64_t b, std::int64_t c) const {
        const CornerLabels l = corner_labels(a, b, c);
        return std::all_of(l.begin(), l.end(), [&](std::uint16_t v) { return v == l[0]; });
    }
    CornerSheets sheets(std::int64_t a, std::int64_t b, std::int64_t c) const {
        if (uniform(a, b, c)) return CornerSheets{0, {-1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1}};
        return corner_sheets(neighbourhood(a, b, c));
    }
    /// A meshed label that is not manifold at the corner, else 0.
    std::uint16_t conflict(std::int64_t a, std::int64_t b, std::int64_t c) const {
        // With two labels the rules of corner_sheets.h leave no conflict here (a label's two pairs
        // at an edge share a sheet only where it wraps round, and wrapping round at both ends is
        // bridged); an edge shared with a corner of more labels is checked from that end.
        if (at_most_two_labels(a, b, c)) return 0;
        const CornerNeighbourhood n = neighbourhood(a, b, c);
        return corner_conflict(
            n, corner_sheets(n), [&](std::uint16_t label) { return meshed[label] != 0; },
            [&](int edge) {
                std::array<std::int64_t, 3> far{a, b, c};
                far[edge / 2] += edge % 2 ? 1 : -1;
                return sheets(far[0], far[1], far[2]);
            });
    }
};

/// Changes voxels until every meshed label is manifold at every corner (corner_sheets());
/// returns how many voxels changed. Throws Error when that does not settle.
std::uint64_t make_manifold(LabelGrid& grid);

}  // namespace vdbmesh::labels_detail
