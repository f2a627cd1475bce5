// Normals by PCA over the k nearest neighbours, oriented towards the scanner or over a
// minimum spanning tree (Hoppe et al. 1992); isolated points removed.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>
#include <tuple>

#include "kdtree.h"
#include "points_internal.h"
#include "vdbmesh/error.h"
#include "vdbmesh/points.h"
#include "vdbmesh/union_find.h"

namespace vdbmesh {

namespace points_detail {

PcaResult pca_normal(const std::vector<Vec3d>& points, const std::vector<std::size_t>& index) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::size_t i : index) mean += Eigen::Vector3d(points[i][0], points[i][1], points[i][2]);
    mean /= double(index.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (std::size_t i : index) {
        const Eigen::Vector3d d = Eigen::Vector3d(points[i][0], points[i][1], points[i][2]) - mean;
        cov += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(cov);
    const Eigen::Vector3d n = solver.eigenvectors().col(0).normalized();
    const Eigen::Vector3d l = solver.eigenvalues().cwiseMax(0.0);
    const double sum = l.sum();
    PcaResult r;
    r.normal = {n.x(), n.y(), n.z()};
    r.variation = sum > 0 ? l[0] / sum : 0.0;
    return r;
}

}  // namespace points_detail

using points_detail::KdTree;

namespace {

using NeighbourGraph = std::vector<std::uint32_t>;  // k neighbours per point, -1 where fewer
constexpr std::uint32_t kNone = std::uint32_t(-1);

double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
void flip(Vec3d& n) {
    for (double& c : n) c = -c;
}

/// The k-nearest graph made symmetric (an edge from either end), as compressed rows.
struct Adjacency {
    std::vector<std::size_t> first;  // n + 1 offsets into next
    std::vector<std::uint32_t> next;
    Adjacency(const NeighbourGraph& graph, std::size_t n, std::size_t k) : first(n + 1, 0) {
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t m = 0; m < k; ++m)
                if (const std::uint32_t j = graph[i * k + m]; j != kNone) ++first[i + 1], ++first[j + 1];
        std::partial_sum(first.begin(), first.end(), first.begin());
        next.resize(first[n]);
        std::vector<std::size_t> fill(first.begin(), first.end() - 1);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t m = 0; m < k; ++m)
                if (const std::uint32_t j = graph[i * k + m]; j != kNone) next[fill[i]++] = j, next[fill[j]++] = std::uint32_t(i);
    }
};

/// Prim's propagation over the minimum spanning tree of the graph weighted by 1 - |n_i . n_j|
/// (Hoppe et al. 1992), grown from @a start (decided) over the points not @a done: each point
/// reached takes the side of the one it is reached from. Deterministic: ties by point number.
void propagate_orientation(std::vector<Vec3d>& normals, const Adjacency& graph, std::vector<char>& done, std::uint32_t start) {
    using Entry = std::tuple<double, std::uint32_t, std::uint32_t>;  // weight, to, from
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    auto push_edges = [&](std::uint32_t from) {
        for (std::size_t e = graph.first[from]; e < graph.first[from + 1]; ++e) {
            const std::uint32_t to = graph.next[e];
            if (!done[to]) queue.emplace(1.0 - std::abs(dot(normals[from], normals[to])), to, from);
        }
    };
    done[start] = 1;
    push_edges(start);
    while (!queue.empty()) {
        const auto [w, j, from] = queue.top();
        queue.pop();
        if (done[j]) continue;
        done[j] = 1;
        if (dot(normals[from], normals[j]) < 0) flip(normals[j]);
        push_edges(j);
    }
}

/// Range scans: each normal takes the side of its scanner. Points seen at a grazing angle get
/// an unreliable side from it: two rounds of neighbour voting (from the previous round's
/// normals, so any thread count gives the same result) flip those that disagree with most of
/// their neighbours. (Propagating the sides of the face-on normals to the grazing ones over
/// the spanning tree instead changed none of the bunny's figures, for 0.6 s more.)
void orient_towards_scanners(const PointCloud& cloud, std::vector<Vec3d>& normals, const NeighbourGraph& graph, std::size_t k) {
    const std::size_t n = normals.size();
    for (std::size_t i = 0; i < n; ++i)
        if (dot(normals[i], cloud.scan_view[cloud.scan[i]]) < 0) flip(normals[i]);
    for (int round = 0; round < 2; ++round) {
        std::vector<Vec3d> next = normals;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                int agree = 0, disagree = 0;
                for (std::size_t m = 0; m < k; ++m) {
                    const std::uint32_t j = graph[i * k + m];
                    if (j == kNone) continue;
                    const double d = dot(normals[i], normals[j]);
                    agree += d > 0.2;
                    disagree += d < -0.2;
                }
                if (disagree > agree) flip(next[i]);
            }
        });
        normals.swap(next);
    }
}

/// No scanner: each component of the k-nearest graph starts at its highest point, oriented up
/// (+z), and propagates over the minimum spanning tree.
void orient_by_spanning_tree(const PointCloud& cloud, std::vector<Vec3d>& normals, const NeighbourGraph& graph, std::size_t k) {
    const std::size_t n = normals.size();
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        if (cloud.points[a][2] != cloud.points[b][2]) return cloud.points[a][2] > cloud.points[b][2];
        return a < b;
    });
    const Adjacency adjacency(graph, n, k);
    std::vector<char> done(n, 0);
    for (std::size_t start : order) {
        if (done[start]) continue;
        if (normals[start][2] < 0) flip(normals[start]);
        propagate_orientation(normals, adjacency, done, std::uint32_t(start));
    }
}

}  // namespace

void estimate_normals(PointCloud& cloud, const NormalOptions& options) {
    if (cloud.has_normals()) return;
    if (options.neighbours < 3) throw UsageError("normals: expected at least 3 neighbours, got " + std::to_string(options.neighbours));
    const std::size_t n = cloud.points.size();
    if (n < 3) throw Error("normals: need at least 3 points, got " + std::to_string(n));
    const KdTree tree(cloud.points);
    const std::size_t k = std::size_t(options.neighbours);
    std::vector<Vec3d> normals(n);
    NeighbourGraph graph(n * k, kNone);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::size_t> index;
        std::vector<double> dist2;
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            tree.knn(cloud.points[i], k + 1, index, dist2);
            normals[i] = points_detail::pca_normal(cloud.points, index).normal;
            std::size_t m = 0;
            for (std::size_t j : index)
                if (j != i && m < k) graph[i * k + m++] = std::uint32_t(j);
        }
    });
    if (!cloud.scan.empty() && !cloud.scan_view.empty()) {
        orient_towards_scanners(cloud, normals, graph, k);
    } else {
        orient_by_spanning_tree(cloud, normals, graph, k);
    }
    cloud.normals = std::move(normals);
}

std::size_t remove_outliers(PointCloud& cloud, int neighbours, double factor) {
    const std::size_t n = cloud.points.size();
    if (factor <= 0 || n < std::size_t(neighbours) + 2) return 0;
    const KdTree tree(cloud.points);
    std::vector<double> mean(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::size_t> index;
        std::vector<double> dist2;
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            tree.knn(cloud.points[i], std::size_t(neighbours) + 1, index, dist2);
            double s = 0;
            for (double d : dist2) s += std::sqrt(d);
            mean[i] = s / double(neighbours);
        }
    });
    std::vector<double> sorted = mean;
    std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
    const double median = sorted[n / 2];
    const double limit = median * (1.0 + factor);
    std::vector<char> keep(n);
    std::size_t kept = 0;
    for (std::size_t i = 0; i < n; ++i) kept += (keep[i] = mean[i] <= limit);
    if (kept == n) return 0;
    points_detail::keep_points(cloud, keep);
    return n - kept;
}

std::size_t remove_small_clusters(PointCloud& cloud, double min_fraction, int neighbours, double radius_factor) {
    const std::size_t n = cloud.points.size();
    if (min_fraction <= 0 || n < 16) return 0;
    const KdTree tree(cloud.points);
    const std::size_t k = std::size_t(neighbours);
    std::vector<std::uint32_t> graph(n * k, std::uint32_t(-1));
    std::vector<double> nearest(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::size_t> index;
        std::vector<double> dist2;
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            tree.knn(cloud.points[i], k + 1, index, dist2);
            nearest[i] = dist2.size() > 1 ? std::sqrt(dist2[1]) : 0.0;
            for (std::size_t m = 1; m < index.size(); ++m) graph[i * k + m - 1] = std::uint32_t(index[m]);
        }
    });
    std::vector<double> sorted = nearest;
    std::nth_element(sorted.begin(), sorted.begin() + long(n / 2), sorted.end());
    const double radius = radius_factor * sorted[n / 2];
    detail::UnionFind sets(n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t m = 0; m < k; ++m) {
            const std::uint32_t j = graph[i * k + m];
            if (j == std::uint32_t(-1)) continue;
            const Vec3d& a = cloud.points[i];
            const Vec3d& b = cloud.points[j];
            const double d2 = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
            if (d2 > radius * radius) continue;
            sets.unite(std::uint32_t(i), j);
        }
    std::vector<std::size_t> size(n, 0);
    for (std::size_t i = 0; i < n; ++i) ++size[sets.find(std::uint32_t(i))];
    const double limit = min_fraction * double(n);
    std::vector<char> keep(n);
    std::size_t kept = 0;
    for (std::size_t i = 0; i < n; ++i) kept += (keep[i] = double(size[sets.find(std::uint32_t(i))]) >= limit);
    if (kept == n || kept == 0) return 0;
    points_detail::keep_points(cloud, keep);
    return n - kept;
}

namespace points_detail {

void keep_points(PointCloud& cloud, const std::vector<char>& keep) {
    std::size_t o = 0;
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        if (!keep[i]) continue;
        cloud.points[o] = cloud.points[i];
        if (cloud.has_normals()) cloud.normals[o] = cloud.normals[i];
        if (!cloud.scan.empty()) cloud.scan[o] = cloud.scan[i];
        ++o;
    }
    cloud.points.resize(o);
    if (cloud.has_normals()) cloud.normals.resize(o);
    if (!cloud.scan.empty()) cloud.scan.resize(o);
}

}  // namespace points_detail

}  // namespace vdbmesh
