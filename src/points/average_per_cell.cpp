// Points (and normals) averaged per cell of a grid.

#include <algorithm>
#include <array>
#include <cmath>

#include "points_internal.h"

namespace vdbmesh::points_detail {

PointCloud average_per_cell(const PointCloud& cloud, double cell) {
    using Key = std::array<std::int64_t, 3>;
    std::vector<std::pair<Key, std::uint32_t>> keyed(cloud.points.size());
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        Key k;
        for (int a = 0; a < 3; ++a) k[a] = std::int64_t(std::floor(cloud.points[i][a] / cell));
        keyed[i] = {k, std::uint32_t(i)};
    }
    std::sort(keyed.begin(), keyed.end());
    PointCloud out;
    for (std::size_t i = 0; i < keyed.size();) {
        std::size_t j = i;
        Vec3d p{0, 0, 0}, nsum{0, 0, 0};
        while (j < keyed.size() && keyed[j].first == keyed[i].first) {
            const std::uint32_t m = keyed[j].second;
            for (int a = 0; a < 3; ++a) p[a] += cloud.points[m][a], nsum[a] += cloud.normals[m][a];
            ++j;
        }
        const double count = double(j - i);
        for (double& c : p) c /= count;
        const double len = std::sqrt(nsum[0] * nsum[0] + nsum[1] * nsum[1] + nsum[2] * nsum[2]);
        if (len > 1e-9 * count) {  // normals that cancel out: drop the cell
            for (double& c : nsum) c /= len;
            out.points.push_back(p);
            out.normals.push_back(nsum);
        }
        i = j;
    }
    return out;
}

}  // namespace vdbmesh::points_detail
