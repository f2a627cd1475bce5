// Where three or more labels meet so that one of them cannot be given a manifold sheet at a
// corner (corner_sheets(): two of its curves joined through other labels' walls), one of its
// voxels there takes the most common other label among its six neighbours. Rare in real maps.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <map>
#include <string>

#include "labels/label_grid.h"
#include "vdbmesh/error.h"

namespace vdbmesh::labels_detail {
namespace {

constexpr int kMaxRounds = 64;

struct Conflict {
    std::array<std::int64_t, 3> corner;
    std::uint16_t label;
};

/// A corner's conflict reads the voxels up to 3 before it and 2 after it along each axis (its
/// block, the voxels beyond its edges, and their corners' blocks and voxels beyond): the
/// corners a changed voxel can affect, with a margin of one.
constexpr std::int64_t kReachBefore = 3, kReachAfter = 4;

/// The corners (in z, y, x order) near the voxels @a changed where a meshed label is not
/// manifold: every corner that may differ from the last scan.
std::vector<Conflict> conflicts_near(const LabelGrid& grid, const std::vector<std::array<std::int64_t, 3>>& changed) {
    const std::array<std::int64_t, 3> n = grid.corner_dims();
    std::vector<std::array<std::int64_t, 3>> corners;  // (c, b, a): sorted in z, y, x order
    for (const auto& v : changed)
        for (std::int64_t c = std::max<std::int64_t>(0, v[2] - kReachBefore); c <= std::min(n[2] - 1, v[2] + kReachAfter); ++c)
            for (std::int64_t b = std::max<std::int64_t>(0, v[1] - kReachBefore); b <= std::min(n[1] - 1, v[1] + kReachAfter); ++b)
                for (std::int64_t a = std::max<std::int64_t>(0, v[0] - kReachBefore); a <= std::min(n[0] - 1, v[0] + kReachAfter); ++a)
                    corners.push_back({c, b, a});
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    std::vector<Conflict> found;
    for (const auto& [c, b, a] : corners)
        if (const std::uint16_t label = grid.conflict(a, b, c)) found.push_back({{a, b, c}, label});
    return found;
}

/// The corners (in z, y, x order) where a meshed label is not manifold.
std::vector<Conflict> find_conflicts(const LabelGrid& grid) {
    const std::array<std::int64_t, 3> n = grid.corner_dims();
    std::vector<std::vector<Conflict>> per_layer(static_cast<std::size_t>(n[2]));
    tbb::parallel_for(std::int64_t(0), n[2], [&](std::int64_t c) {
        for (std::int64_t b = 0; b < n[1]; ++b)
            for (std::int64_t a = 0; a < n[0]; ++a) {
                if (const std::uint16_t label = grid.conflict(a, b, c)) per_layer[std::size_t(c)].push_back({{a, b, c}, label});
            }
    });
    std::vector<Conflict> all;
    for (const auto& layer : per_layer) all.insert(all.end(), layer.begin(), layer.end());
    return all;
}

/// The most common label other than @a label among the six neighbours of a voxel (ties: the lowest).
std::uint16_t neighbour_label(const LabelGrid& grid, std::int64_t x, std::int64_t y, std::int64_t z, std::uint16_t label) {
    std::map<std::uint16_t, int> votes;
    const std::int64_t step[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    for (const auto& s : step) {
        const std::uint16_t l = grid.at(x + s[0], y + s[1], z + s[2]);
        if (l != label) ++votes[l];
    }
    std::uint16_t best = 0;
    int most = 0;
    for (const auto& [l, count] : votes)
        if (count > most) best = l, most = count;
    return best;
}

}  // namespace

std::uint64_t make_manifold(LabelGrid& grid) {
    std::uint64_t changed = 0;
    // After the first scan only the corners near the voxels just changed can have changed:
    // every conflict found before either changed a voxel or was settled by a change near it.
    std::vector<std::array<std::int64_t, 3>> changed_voxels;
    for (int round = 0; round < kMaxRounds; ++round) {
        const std::vector<Conflict> conflicts = round == 0 ? find_conflicts(grid) : conflicts_near(grid, changed_voxels);
        if (conflicts.empty()) return changed;
        changed_voxels.clear();
        for (const Conflict& conflict : conflicts) {
            const auto [a, b, c] = conflict.corner;
            if (grid.conflict(a, b, c) != conflict.label) continue;  // an earlier change settled it
            const CornerLabels l = grid.corner_labels(a, b, c);
            const int o = int(std::find(l.begin(), l.end(), conflict.label) - l.begin());
            const std::int64_t x = a - 1 + (o & 1), y = b - 1 + (o >> 1 & 1), z = c - 1 + (o >> 2 & 1);
            grid.labels[std::size_t((z * grid.dims[1] + y) * grid.dims[0] + x)] = neighbour_label(grid, x, y, z, conflict.label);
            changed_voxels.push_back({x, y, z});
            ++changed;
        }
    }
    throw Error("label map: some labels still meet without a manifold surface after " + std::to_string(kMaxRounds) +
                " rounds of changing voxels (" + std::to_string(changed) + " changed)");
}

}  // namespace vdbmesh::labels_detail
