// Adaptive decimation (the method's chapter 2.4): importance = normal variation over the
// relative density; leaves and points removed with probabilities from their importances.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "kdtree.h"
#include "points_internal.h"
#include "vdbmesh/error.h"
#include "vdbmesh/points.h"

namespace vdbmesh {

PointCloud decimate_points(const PointCloud& input, const DecimateOptions& options) {
    if (!(options.fraction >= 0 && options.fraction < 1))
        throw UsageError("--decimate: expected a fraction in [0, 1), got " + std::to_string(options.fraction));
    PointCloud cloud = input;
    if (options.fraction == 0 || cloud.points.size() < 10) return cloud;
    if (!cloud.has_normals()) estimate_normals(cloud, {options.neighbours});
    const std::size_t n = cloud.points.size();
    const points_detail::KdTree tree(cloud.points);
    std::vector<double> variation(n), spacing(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::size_t> index;
        std::vector<double> dist2;
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            tree.knn(cloud.points[i], std::size_t(options.neighbours) + 1, index, dist2);
            variation[i] = points_detail::pca_normal(cloud.points, index).variation;
            spacing[i] = std::sqrt(dist2.back());
        }
    });
    // Relative density: (mean spacing / own spacing)^2; importance = variation / density.
    double mean_spacing = 0;
    for (double s : spacing) mean_spacing += s;  // serial: the same sum for any thread count
    mean_spacing /= double(n);
    double mean_variation = 0;
    for (double v : variation) mean_variation += v;
    mean_variation /= double(n);
    const double eps = mean_variation + 1e-12;  // density matters as much as a mean variation
    std::vector<double> importance(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double density = std::pow(mean_spacing / std::max(spacing[i], 1e-300), 2.0);
        importance[i] = (variation[i] + eps) / density;
    }
    // Leaves of a median partition on the longest axis of the points.
    std::vector<std::vector<std::uint32_t>> leaves;
    {
        std::vector<std::vector<std::uint32_t>> stack(1);
        stack[0].resize(n);
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
    }
    // How many go from each leaf: proportional to size / mean importance, never below the minimum.
    const std::size_t target = std::size_t(std::llround(options.fraction * double(n)));
    std::vector<double> weight(leaves.size());
    std::vector<std::size_t> removable(leaves.size()), remove(leaves.size(), 0);
    for (std::size_t l = 0; l < leaves.size(); ++l) {
        double s = 0;
        for (std::uint32_t i : leaves[l]) s += importance[i];
        const double mean = s / double(leaves[l].size());
        weight[l] = double(leaves[l].size()) / mean;
        const std::size_t keep_min = std::min<std::size_t>(leaves[l].size(), std::size_t(std::max(options.min_per_leaf, 0)));
        removable[l] = leaves[l].size() - keep_min;
    }
    std::size_t removed = 0;
    for (int round = 0; round < 20 && removed < target; ++round) {
        double total = 0;
        for (std::size_t l = 0; l < leaves.size(); ++l)
            if (remove[l] < removable[l]) total += weight[l];
        if (total <= 0) break;
        const double left = double(target - removed);
        std::size_t added = 0;
        for (std::size_t l = 0; l < leaves.size() && removed + added < target; ++l) {
            if (remove[l] >= removable[l]) continue;
            const std::size_t want = std::max<std::size_t>(1, std::size_t(std::floor(left * weight[l] / total)));
            const std::size_t take = std::min({want, removable[l] - remove[l], target - removed - added});
            remove[l] += take;
            added += take;
        }
        removed += added;
        if (added == 0) break;
    }
    // Within a leaf: weighted sampling without replacement (keys u^(1/w), w = 1/importance).
    std::mt19937_64 rng(options.seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::vector<char> keep(n, 1);
    for (std::size_t l = 0; l < leaves.size(); ++l) {
        std::vector<std::pair<double, std::uint32_t>> keys;
        keys.reserve(leaves[l].size());
        for (std::uint32_t i : leaves[l]) {
            const double u = std::max(uniform(rng), 1e-300);
            keys.emplace_back(std::log(u) * importance[i], i);  // log(u^(1/w)) with w = 1/importance
        }
        if (remove[l] == 0) continue;
        std::sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) {
            return a.first != b.first ? a.first > b.first : a.second < b.second;
        });
        for (std::size_t k = 0; k < remove[l]; ++k) keep[keys[k].second] = 0;
    }
    points_detail::keep_points(cloud, keep);
    return cloud;
}

}  // namespace vdbmesh
