// Adaptive decimation (the method's chapter 2.4): a point's importance is its normal variation
// over its density relative to its leaf; leaves lose points in proportion to how unimportant
// they are, and within a leaf the least important points are the likeliest to go.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "kdtree.h"
#include "points_internal.h"
#include "vdbmesh/error.h"
#include "vdbmesh/points.h"

namespace vdbmesh {

namespace points_detail {

namespace {

/// A uniform number in (0, 1) from the seed, the leaf and the point (splitmix64): each leaf
/// draws on its own, so the choice does not depend on the order the leaves are visited in.
double uniform_draw(std::uint64_t seed, std::uint64_t leaf, std::uint64_t point) {
    std::uint64_t z = seed ^ (leaf * 0x9E3779B97F4A7C15ull) ^ (point * 0xD1B54A32D192ED69ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double(z >> 11) + 0.5) * 0x1.0p-53;
}

/// How many points each leaf gives up: @a target in all, shared in proportion to @a weight,
/// never more than @a removable of a leaf (what a full leaf cannot give goes to the others).
std::vector<std::size_t> removal_quotas(const std::vector<double>& weight, const std::vector<std::size_t>& removable, std::size_t target) {
    std::vector<std::size_t> quota(weight.size(), 0);
    std::size_t removed = 0;
    while (removed < target) {
        double total = 0;
        for (std::size_t l = 0; l < weight.size(); ++l)
            if (quota[l] < removable[l]) total += weight[l];
        if (total <= 0) break;
        const double left = double(target - removed);
        std::size_t added = 0;
        for (std::size_t l = 0; l < weight.size() && removed + added < target; ++l) {
            if (quota[l] >= removable[l] || weight[l] <= 0) continue;
            const auto share = std::max<std::size_t>(1, std::size_t(std::floor(left * weight[l] / total)));
            const std::size_t take = std::min({share, removable[l] - quota[l], target - removed - added});
            quota[l] += take;
            added += take;
        }
        removed += added;
        if (added == 0) break;
    }
    return quota;
}

}  // namespace

PointFeatures point_features(const std::vector<Vec3d>& points, const KdTree& tree, int neighbours) {
    const std::size_t n = points.size();
    PointFeatures f;
    f.variation.resize(n);
    f.density.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::size_t> index;
        std::vector<double> dist2;
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            tree.knn(points[i], std::size_t(neighbours) + 1, index, dist2);
            f.variation[i] = pca_normal(points, index).variation;
            // Points per area of the disc reaching the k-th neighbour (pi left out: only ratios count).
            f.density[i] = double(index.size() - 1) / std::max(dist2.back(), 1e-300);
        }
    });
    return f;
}

void decimate_leaves(std::vector<std::vector<std::uint32_t>>& leaves, const PointFeatures& features, const DecimateOptions& options) {
    if (!(options.fraction >= 0 && options.fraction < 1))
        throw UsageError("decimate: expected a fraction in [0, 1), got " + std::to_string(options.fraction));
    if (options.fraction == 0 || leaves.empty()) return;
    // Importance = variation / relative density, the density relative to the leaf's mean (the
    // leaf's own density); a leaf's total importance is the sum over its points.
    std::vector<std::vector<double>> importance(leaves.size());
    std::vector<double> total(leaves.size(), 0.0);
    std::vector<std::size_t> removable(leaves.size());
    std::size_t all = 0;
    for (std::size_t l = 0; l < leaves.size(); ++l) {
        const auto& leaf = leaves[l];
        double mean_density = 0;
        for (std::uint32_t i : leaf) mean_density += features.density[i];
        mean_density /= double(std::max<std::size_t>(leaf.size(), 1));
        importance[l].reserve(leaf.size());
        for (std::uint32_t i : leaf) {
            const double relative_density = features.density[i] / std::max(mean_density, 1e-300);
            importance[l].push_back(features.variation[i] / relative_density);
            total[l] += importance[l].back();
        }
        removable[l] = leaf.size() - std::min(leaf.size(), std::size_t(std::max(options.min_per_leaf, 0)));
        all += leaf.size();
    }
    // A leaf is chosen with a probability of 1 - total / largest total: the quotas are those
    // probabilities' expected shares.
    const double largest = *std::max_element(total.begin(), total.end());
    std::vector<double> weight(leaves.size());
    for (std::size_t l = 0; l < leaves.size(); ++l) weight[l] = largest > 0 ? 1.0 - total[l] / largest : 1.0;
    const auto target = std::size_t(std::llround(options.fraction * double(all)));
    const std::vector<std::size_t> quota = removal_quotas(weight, removable, target);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::pair<double, std::uint32_t>> keys;
        for (std::size_t l = r.begin(); l < r.end(); ++l) {
            if (quota[l] == 0) continue;
            auto& leaf = leaves[l];
            const double most = *std::max_element(importance[l].begin(), importance[l].end());
            // Weighted sampling without replacement (Efraimidis and Spirakis: the largest keys
            // u^(1/w), here their logarithms) with w = 1 - importance / the leaf's largest.
            keys.clear();
            for (std::size_t m = 0; m < leaf.size(); ++m) {
                const double w = most > 0 ? 1.0 - importance[l][m] / most : 1.0;
                const double u = uniform_draw(options.seed, l, leaf[m]);
                keys.emplace_back(w > 0 ? std::log(u) / w : -HUGE_VAL, leaf[m]);
            }
            std::sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) {
                return a.first != b.first ? a.first > b.first : a.second < b.second;
            });
            std::vector<std::uint32_t> kept;
            kept.reserve(leaf.size() - quota[l]);
            for (std::size_t k = quota[l]; k < keys.size(); ++k) kept.push_back(keys[k].second);
            std::sort(kept.begin(), kept.end());
            leaf.swap(kept);
        }
    });
}

}  // namespace points_detail

PointCloud decimate_points(const PointCloud& input, const DecimateOptions& options) {
    if (!(options.fraction >= 0 && options.fraction < 1))
        throw UsageError("--decimate: expected a fraction in [0, 1), got " + std::to_string(options.fraction));
    PointCloud cloud = input;
    if (options.fraction == 0 || cloud.points.size() < 10) return cloud;
    const points_detail::KdTree tree(cloud.points);
    const points_detail::PointFeatures features = points_detail::point_features(cloud.points, tree, options.neighbours);
    // Leaves of a median partition on the longest axis of the points (disjoint).
    std::vector<std::vector<std::uint32_t>> leaves, stack(1);
    stack[0].resize(cloud.points.size());
    std::iota(stack[0].begin(), stack[0].end(), 0u);
    while (!stack.empty()) {
        std::vector<std::uint32_t> idx = std::move(stack.back());
        stack.pop_back();
        if (idx.size() <= std::size_t(options.leaf_points)) {
            leaves.push_back(std::move(idx));
            continue;
        }
        Vec3d lo = cloud.points[idx[0]], hi = lo;
        for (std::uint32_t i : idx)
            for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], cloud.points[i][a]), hi[a] = std::max(hi[a], cloud.points[i][a]);
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
        const auto mid = idx.begin() + long(idx.size() / 2);
        std::nth_element(idx.begin(), mid, idx.end(), [&](std::uint32_t a, std::uint32_t b) {
            if (cloud.points[a][axis] != cloud.points[b][axis]) return cloud.points[a][axis] < cloud.points[b][axis];
            return a < b;
        });
        std::vector<std::uint32_t> right(mid, idx.end());
        idx.resize(idx.size() / 2);
        stack.push_back(std::move(right));
        stack.push_back(std::move(idx));
    }
    points_detail::decimate_leaves(leaves, features, options);
    std::vector<char> keep(cloud.points.size(), 0);
    for (const auto& leaf : leaves)
        for (std::uint32_t i : leaf) keep[i] = 1;
    points_detail::keep_points(cloud, keep);
    return cloud;
}

}  // namespace vdbmesh
