// Adaptive decimation (the method's chapter 2.4): a point's importance is its normal variation
// over its density relative to its leaf; unimportant leaves and, within them, unimportant
// points are the likeliest to go.

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

void decimate_leaves(std::vector<std::vector<std::uint32_t>>& leaves, std::size_t points, const PointFeatures& features,
                     const DecimateOptions& options) {
    if (!(options.fraction >= 0 && options.fraction < 1))
        throw UsageError("decimate: expected a fraction in [0, 1), got " + std::to_string(options.fraction));
    if (options.fraction == 0 || leaves.empty()) return;
    // Importance = variation / relative density, the density relative to the leaf's mean (the
    // leaf's own density); a leaf's total importance is the sum over its points. A point held
    // by several leaves (the overlaps) is judged in the first of them.
    constexpr auto kNoLeaf = std::uint32_t(-1);
    std::vector<std::uint32_t> home(points, kNoLeaf);
    std::vector<double> importance(points, 0.0), most(leaves.size(), 0.0), total(leaves.size(), 0.0);
    for (std::size_t l = 0; l < leaves.size(); ++l) {
        double mean_density = 0;
        for (std::uint32_t i : leaves[l]) mean_density += features.density[i];
        mean_density /= double(std::max<std::size_t>(leaves[l].size(), 1));
        for (std::uint32_t i : leaves[l]) {
            const double relative_density = features.density[i] / std::max(mean_density, 1e-300);
            const double v = features.variation[i] / relative_density;
            total[l] += v;
            if (home[i] != kNoLeaf) continue;
            home[i] = std::uint32_t(l);
            importance[i] = v;
            most[l] = std::max(most[l], v);
        }
    }
    // The method picks a leaf with probability 1 - total / largest total, then a point of it
    // with probability 1 - importance / the leaf's largest: a point goes with the product, by
    // weighted sampling without replacement (Efraimidis and Spirakis: the largest keys u^(1/w),
    // here their logarithms).
    const double largest = *std::max_element(total.begin(), total.end());
    std::vector<std::pair<double, std::uint32_t>> keys;
    keys.reserve(points);
    for (std::size_t i = 0; i < points; ++i) {
        if (home[i] == kNoLeaf) continue;
        const std::uint32_t l = home[i];
        const double leaf_weight = largest > 0 ? 1.0 - total[l] / largest : 1.0;
        const double point_weight = most[l] > 0 ? 1.0 - importance[i] / most[l] : 1.0;
        const double w = leaf_weight * point_weight;
        keys.emplace_back(w > 0 ? std::log(uniform_draw(options.seed, l, i)) / w : -HUGE_VAL, std::uint32_t(i));
    }
    std::sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first : a.second < b.second; });
    // Remove in that order from every leaf holding the point, skipping points whose removal
    // would leave some leaf below the minimum.
    std::vector<std::size_t> member_first(points + 1, 0);
    for (const auto& leaf : leaves)
        for (std::uint32_t i : leaf) ++member_first[i + 1];
    std::partial_sum(member_first.begin(), member_first.end(), member_first.begin());
    std::vector<std::uint32_t> member(member_first.back());
    {
        std::vector<std::size_t> fill(member_first.begin(), member_first.end() - 1);
        for (std::size_t l = 0; l < leaves.size(); ++l)
            for (std::uint32_t i : leaves[l]) member[fill[i]++] = std::uint32_t(l);
    }
    std::vector<std::size_t> left(leaves.size());
    for (std::size_t l = 0; l < leaves.size(); ++l) left[l] = leaves[l].size();
    const auto minimum = std::size_t(std::max(options.min_per_leaf, 0));
    const auto target = std::size_t(std::llround(options.fraction * double(keys.size())));
    std::vector<char> removed(points, 0);
    std::size_t count = 0;
    for (const auto& [key, i] : keys) {
        if (count == target) break;
        bool allowed = true;
        for (std::size_t e = member_first[i]; e < member_first[i + 1] && allowed; ++e) allowed = left[member[e]] > minimum;
        if (!allowed) continue;
        for (std::size_t e = member_first[i]; e < member_first[i + 1]; ++e) --left[member[e]];
        removed[i] = 1;
        ++count;
    }
    for (auto& leaf : leaves) leaf.erase(std::remove_if(leaf.begin(), leaf.end(), [&](std::uint32_t i) { return removed[i] != 0; }), leaf.end());
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
    points_detail::decimate_leaves(leaves, cloud.points.size(), features, options);
    std::vector<char> keep(cloud.points.size(), 0);
    for (const auto& leaf : leaves)
        for (std::uint32_t i : leaf) keep[i] = 1;
    points_detail::keep_points(cloud, keep);
    return cloud;
}

}  // namespace vdbmesh
