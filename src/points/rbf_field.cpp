// The partition-of-unity RBF field: an overlapping binary partition (median split on the
// longest axis), a polyharmonic r^3 + linear RBF per leaf with Carr's off-surface
// constraints, blended by smooth weights that form a partition of unity.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "kdtree.h"
#include "points_internal.h"
#include "vdbmesh/error.h"
#include "vdbmesh/points.h"

namespace vdbmesh {

namespace {

struct Node {
    Vec3d lo, hi;
    int axis = -1;        // split axis; -1 for a leaf
    double split = 0;     // the median
    double half = 0;      // half the overlap: the children blend over [split - half, split + half]
    int child[2] = {-1, -1};
    int leaf = -1;
};

struct Leaf {
    Vec3d centre{0, 0, 0};
    double scale = 1;                     // local coordinates: (x - centre) / scale
    std::vector<double> x, y, z, lambda;  // the RBF centres (local) and their weights
    double poly[4] = {0, 0, 0, 0};        // a0 + a . x
};

inline double squared_distance(const Vec3d& a, const Vec3d& b) {
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

/// 0 at t <= 0, 1 at t >= 1, C1 in between; s(t) + s(1 - t) = 1.
inline double smooth_step(double t) {
    if (t <= 0) return 0;
    if (t >= 1) return 1;
    return t * t * (3 - 2 * t);
}

}  // namespace

struct RbfField::Impl {
    std::vector<Node> nodes;
    std::vector<Leaf> leaves;
    Vec3d lo, hi;
    double spacing = 0;
    std::vector<Vec3d> points;
    std::unique_ptr<points_detail::KdTree> tree;
    PointCloud coarse;  // the points averaged per cell of 8 median spacings: the far field's planes
    std::unique_ptr<points_detail::KdTree> coarse_tree;
    std::size_t fitted_points = 0;
    double trust = 0;  // beyond this distance from the points the field blends into Hoppe's

    /// Visits the leaves whose fits blend at @a p, with their weights: depth-first, left before
    /// right, so the sum has the same order for every point.
    template <class Visit>
    void visit_leaves(int node, const Vec3d& p, double weight, Visit&& visit) const {
        const Node& nd = nodes[std::size_t(node)];
        if (nd.leaf >= 0) {
            visit(std::uint32_t(nd.leaf), weight);
            return;
        }
        const double t = (p[std::size_t(nd.axis)] - (nd.split - nd.half)) / (2 * nd.half);
        const double right = smooth_step(t);
        if (right < 1) visit_leaves(nd.child[0], p, weight * (1 - right), visit);
        if (right > 0) visit_leaves(nd.child[1], p, weight * right, visit);
    }

    /// Hoppe's signed distance to the tangent planes at @a p, averaged over its 8 nearest points
    /// of the coarse cloud.
    double tangent_plane_distance(const Vec3d& p) const {
        std::vector<std::size_t> index;
        std::vector<double> dist2;
        coarse_tree->knn(p, 8, index, dist2);
        double g = 0;
        for (std::size_t i : index) {
            const Vec3d& q = coarse.points[i];
            const Vec3d& n = coarse.normals[i];
            g += (p[0] - q[0]) * n[0] + (p[1] - q[1]) * n[1] + (p[2] - q[2]) * n[2];
        }
        return g / double(index.size());
    }

    std::vector<double> blend_distances(const Vec3d* p, std::size_t count) const;
    void values(const Vec3d* p, std::size_t count, double* out) const;
};

namespace {

/// Points evaluated together against one leaf (the inner loop runs over them: vectorised).
constexpr std::size_t kChunk = 64;

/// out[j] = the local fit of @a leaf at world points (x[j], y[j], z[j]), j < m <= kChunk. The
/// sum over the centres runs in their order for every point, whatever m.
void evaluate_leaf(const Leaf& leaf, const double* x, const double* y, const double* z, std::size_t m, double* out) {
    const double inv = 1.0 / leaf.scale;
    double px[kChunk], py[kChunk], pz[kChunk], sum[kChunk];
    for (std::size_t j = 0; j < m; ++j) {
        px[j] = (x[j] - leaf.centre[0]) * inv, py[j] = (y[j] - leaf.centre[1]) * inv, pz[j] = (z[j] - leaf.centre[2]) * inv;
        sum[j] = 0;
    }
    const std::size_t n = leaf.x.size();
    for (std::size_t c = 0; c < n; ++c) {
        const double cx = leaf.x[c], cy = leaf.y[c], cz = leaf.z[c], lambda = leaf.lambda[c];
        for (std::size_t j = 0; j < m; ++j) {
            const double dx = px[j] - cx, dy = py[j] - cy, dz = pz[j] - cz;
            const double r2 = dx * dx + dy * dy + dz * dz;
            sum[j] += lambda * (r2 * std::sqrt(r2));
        }
    }
    for (std::size_t j = 0; j < m; ++j)
        out[j] = (sum[j] + leaf.poly[0] + leaf.poly[1] * px[j] + leaf.poly[2] * py[j] + leaf.poly[3] * pz[j]) * leaf.scale;
}

}  // namespace

std::vector<double> RbfField::Impl::blend_distances(const Vec3d* p, std::size_t count) const {
    // Only distances between trust and twice trust matter (the blend): a point within trust of
    // the last nearest point found is within trust (0 stands for that), and one with no point
    // within twice trust is beyond it (2 * trust stands for that).
    std::vector<double> distance(count, 0.0);
    Vec3d lo = p[0], hi = p[0];
    for (std::size_t i = 0; i < count; ++i)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[i][a]), hi[a] = std::max(hi[a], p[i][a]);
    const double half_diagonal = 0.5 * std::sqrt(squared_distance(lo, hi));
    const Vec3d centre{0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    // A compact batch (a block's cubes, cells or voxels): one search for every point that can be
    // within twice trust of one of it, then the nearest of those by brute force (vectorised).
    // A spread batch: one search per point.
    const bool compact = count >= 8 && half_diagonal <= 8 * trust;
    std::vector<std::size_t> near;
    std::vector<double> x, y, z;
    if (compact) {
        tree->within(centre, half_diagonal + 2 * trust, near);
        std::sort(near.begin(), near.end());
        for (std::size_t j : near) x.push_back(points[j][0]), y.push_back(points[j][1]), z.push_back(points[j][2]);
    }
    const double reach2 = 4 * trust * trust;
    std::size_t nearest = tree->nearest(p[0]);
    for (std::size_t i = 0; i < count; ++i) {
        if (squared_distance(p[i], points[nearest]) <= trust * trust) continue;
        if (!compact) {
            double d2 = 0;
            nearest = tree->nearest(p[i], &d2);
            distance[i] = std::sqrt(d2);
            continue;
        }
        const double px = p[i][0], py = p[i][1], pz = p[i][2];
        double best = reach2;
        for (std::size_t j = 0; j < near.size(); ++j) {
            const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
            best = std::min(best, dx * dx + dy * dy + dz * dz);
        }
        if (best >= reach2) {
            distance[i] = 2 * trust;
            continue;
        }
        distance[i] = std::sqrt(best);
        for (std::size_t j = 0; j < near.size(); ++j) {
            const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
            if (dx * dx + dy * dy + dz * dz == best) {
                nearest = near[j];
                break;
            }
        }
    }
    return distance;
}

void RbfField::Impl::values(const Vec3d* p, std::size_t count, double* out) const {
    if (count == 0) return;
    // The blend's terms, point by point in visiting order: (leaf, point, weight); then grouped
    // by leaf so that each leaf's centres are read once for all its points.
    struct Term {
        std::uint32_t leaf, point;
        double weight, value;
    };
    std::vector<Term> terms;
    terms.reserve(4 * count);
    const std::vector<double> distance = blend_distances(p, count);
    for (std::size_t i = 0; i < count; ++i)
        if (distance[i] < 2 * trust)
            visit_leaves(0, p[i], 1.0, [&](std::uint32_t leaf, double w) { terms.push_back({leaf, std::uint32_t(i), w, 0.0}); });
    // Grouped by leaf, terms in their order within a leaf (the key holds both).
    std::vector<std::uint64_t> order(terms.size());
    for (std::size_t t = 0; t < terms.size(); ++t) order[t] = std::uint64_t(terms[t].leaf) << 32 | std::uint64_t(t);
    std::sort(order.begin(), order.end());
    for (std::uint64_t& key : order) key &= 0xffffffffu;
    double x[kChunk], y[kChunk], z[kChunk], v[kChunk];
    for (std::size_t first = 0; first < order.size();) {
        const std::uint32_t leaf = terms[order[first]].leaf;
        std::size_t last = first;
        while (last < order.size() && terms[order[last]].leaf == leaf && last - first < kChunk) ++last;
        for (std::size_t t = first; t < last; ++t) {
            const Vec3d& q = p[terms[order[t]].point];
            x[t - first] = q[0], y[t - first] = q[1], z[t - first] = q[2];
        }
        evaluate_leaf(leaves[leaf], x, y, z, last - first, v);
        for (std::size_t t = first; t < last; ++t) terms[order[t]].value = v[t - first];
        first = last;
    }
    std::fill(out, out + count, 0.0);
    for (const Term& t : terms) out[t.point] += t.weight * t.value;
    // Away from the points the local fits only extrapolate (and may change sign): Hoppe's
    // distance takes over between trust and twice trust.
    for (std::size_t i = 0; i < count; ++i) {
        if (distance[i] <= trust) continue;
        const double g = tangent_plane_distance(p[i]);
        if (distance[i] >= 2 * trust) {
            out[i] = g;
        } else {
            const double w = smooth_step((distance[i] - trust) / trust);
            out[i] = (1 - w) * out[i] + w * g;
        }
    }
}

RbfField::~RbfField() = default;
RbfField::RbfField(RbfField&&) noexcept = default;
RbfField& RbfField::operator=(RbfField&&) noexcept = default;

RbfField::RbfField(const PointCloud& cloud, const RbfOptions& options) : impl_(std::make_unique<Impl>()) {
    const std::size_t n = cloud.points.size();
    if (!cloud.has_normals() || cloud.normals.size() != n) throw UsageError("RBF field: the points need normals");
    if (n < 4) throw Error("RBF field: need at least 4 points, got " + std::to_string(n));
    if (options.leaf_min < 4) throw UsageError("RBF field: leaf_min must be at least 4");
    if (!(options.overlap > 0 && options.overlap < 0.5)) throw UsageError("RBF field: overlap must be in (0, 0.5)");
    Impl& m = *impl_;
    const std::vector<Vec3d>& P = cloud.points;
    const std::vector<Vec3d>& N = cloud.normals;

    // The median and 90th percentile of the nearest-neighbour distance (over an even subset).
    double wide_spacing = 0;
    m.points = P;
    m.tree = std::make_unique<points_detail::KdTree>(m.points);
    {
        const points_detail::KdTree& tree = *m.tree;
        const std::size_t step = std::max<std::size_t>(1, n / 20000);
        std::vector<double> d;
        std::vector<std::size_t> idx;
        std::vector<double> d2;
        for (std::size_t i = 0; i < n; i += step) {
            tree.knn(P[i], 2, idx, d2);
            if (d2.size() == 2) d.push_back(std::sqrt(d2[1]));
        }
        std::sort(d.begin(), d.end());
        m.spacing = d.empty() ? 0 : d[d.size() / 2];
        wide_spacing = d.empty() ? 0 : d[d.size() * 9 / 10];
    }
    Vec3d lo = P[0], hi = P[0];
    for (const Vec3d& p : P)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    if (!(longest > 0)) throw Error("RBF field: the points are all at one place");
    if (!(m.spacing > 0)) m.spacing = longest * 1e-3;
    const double margin = 0.1 * longest;
    for (int a = 0; a < 3; ++a) lo[a] -= margin, hi[a] += margin;
    m.lo = lo, m.hi = hi;
    const double off = options.off_surface > 0 ? options.off_surface : 0.5 * m.spacing;
    // Far from the points the local fits extrapolate and may cross zero: at 4 median spacings
    // (before session 8) the bunny grew blisters 2 to 3 mm off the scans (10,600 vertices
    // beyond 0.5% of its diagonal from bun_zipper; 2,700 at 2). Twice the 90th percentile
    // still covers the gaps of randomly spread points (a sphere of 5,000 random points came 1.6%
    // off its radius at twice the median).
    m.trust = options.trust > 0 ? options.trust : 2.0 * std::max(wide_spacing, m.spacing);
    // The far field only needs the coarse shape, and its sign deep inside must not follow the
    // few nearest points: their normals can be wrong (a scan's stray inner layer mixed into the
    // PCA, normals at 90 degrees to the surface made 1.6 cm deep pockets in the bunny's head).
    // Averaged per cell of 8 spacings, a few bad normals are outvoted by the good ones around
    // them (cells of 2.5 spacings let the pocket back).
    m.coarse = points_detail::average_per_cell(cloud, 8.0 * m.spacing);
    if (m.coarse.points.empty()) m.coarse = cloud;
    m.coarse_tree = std::make_unique<points_detail::KdTree>(m.coarse.points);

    // The partition (serial, deterministic).
    struct Pending {
        int node;
        std::vector<std::uint32_t> index;
    };
    std::vector<Pending> stack;
    std::vector<int> leaf_nodes;                        // each leaf's node
    std::vector<std::vector<std::uint32_t>> leaf_points;  // and its points
    m.nodes.push_back(Node{lo, hi});
    {
        std::vector<std::uint32_t> all(n);
        std::iota(all.begin(), all.end(), 0u);
        stack.push_back({0, std::move(all)});
    }
    const std::size_t max_leaf = 2 * std::size_t(options.leaf_min);
    while (!stack.empty()) {
        Pending job = std::move(stack.back());
        stack.pop_back();
        Node nd = m.nodes[std::size_t(job.node)];
        if (job.index.size() <= max_leaf) {
            m.nodes[std::size_t(job.node)].leaf = int(leaf_points.size());
            leaf_nodes.push_back(job.node);
            leaf_points.push_back(std::move(job.index));
            continue;
        }
        // The longest axis of the points' box (the cell's own box may be mostly empty).
        Vec3d plo = P[job.index[0]], phi = plo;
        for (std::uint32_t i : job.index)
            for (int a = 0; a < 3; ++a) plo[a] = std::min(plo[a], P[i][a]), phi[a] = std::max(phi[a], P[i][a]);
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (phi[a] - plo[a] > phi[axis] - plo[axis]) axis = a;
        const double extent = phi[axis] - plo[axis];
        std::vector<double> c(job.index.size());
        for (std::size_t i = 0; i < c.size(); ++i) c[i] = P[job.index[i]][std::size_t(axis)];
        std::nth_element(c.begin(), c.begin() + long(c.size() / 2), c.end());
        const double median = c[c.size() / 2];
        double half = std::max(options.overlap * extent, 0.5 * m.spacing);
        double split = median;
        std::vector<std::uint32_t> li, ri;
        bool ok = false;
        for (int attempt = 0; attempt < 6 && !ok; ++attempt, half *= 0.5) {
            split = std::clamp(median, nd.lo[axis] + 2 * half, nd.hi[axis] - 2 * half);
            li.clear();
            ri.clear();
            for (std::uint32_t i : job.index) {
                const double x = P[i][std::size_t(axis)];
                if (x <= split + half) li.push_back(i);
                if (x >= split - half) ri.push_back(i);
            }
            // Both sides must shrink (the overlap may not hold most points).
            ok = li.size() <= job.index.size() * 3 / 4 && ri.size() <= job.index.size() * 3 / 4;
            if (ok) break;
        }
        if (!ok) {
            m.nodes[std::size_t(job.node)].leaf = int(leaf_points.size());
            leaf_nodes.push_back(job.node);
            leaf_points.push_back(std::move(job.index));
            continue;
        }
        Node left{nd.lo, nd.hi}, right{nd.lo, nd.hi};
        left.hi[std::size_t(axis)] = split + half;
        right.lo[std::size_t(axis)] = split - half;
        Node& parent = m.nodes[std::size_t(job.node)];
        parent.axis = axis;
        parent.split = split;
        parent.half = half;
        const int l = int(m.nodes.size());
        m.nodes.push_back(left);
        m.nodes.push_back(right);
        m.nodes[std::size_t(job.node)].child[0] = l;
        m.nodes[std::size_t(job.node)].child[1] = l + 1;
        stack.push_back({l + 1, std::move(ri)});
        stack.push_back({l, std::move(li)});
    }

    // Decimation after the partition, before the fits (the method's order): the leaves keep
    // the boxes of all the points, each fit gets fewer centres. A point goes from every leaf
    // holding it (the overlaps hold each point in about 4 leaves: dropping it from one only
    // makes neighbouring fits disagree).
    if (options.decimate.fraction > 0)
        points_detail::decimate_leaves(leaf_points, n, points_detail::point_features(P, *m.tree, options.decimate.neighbours),
                                       options.decimate);
    std::vector<char> fitted(n, 0);
    for (const auto& leaf : leaf_points)
        for (std::uint32_t i : leaf) fitted[i] = 1;
    m.fitted_points = std::size_t(std::count(fitted.begin(), fitted.end(), char(1)));
    // A point removed is merged into its nearest kept point (the mean of their positions and
    // of their normals) rather than thrown away: on scans, a point's offset from the surface is
    // mostly noise, which the mean reduces, where dropping it raised the bunny's mean distance
    // by 23% at 30% (whatever the importance's neighbourhood).
    std::vector<Vec3d> fit_points = P, fit_normals = N;
    if (m.fitted_points < n) {
        std::vector<std::uint32_t> into(n, std::uint32_t(-1));
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
            std::vector<std::size_t> idx;
            std::vector<double> d2;
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                if (fitted[i]) continue;
                m.tree->knn(P[i], 16, idx, d2);
                for (std::size_t j : idx)
                    if (fitted[j]) {
                        into[i] = std::uint32_t(j);
                        break;
                    }
            }
        });
        std::vector<Vec3d> sum_p = P, sum_n = N;
        std::vector<double> count(n, 1.0);
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint32_t j = into[i];
            if (j == std::uint32_t(-1)) continue;
            for (int a = 0; a < 3; ++a) sum_p[j][a] += P[i][a], sum_n[j][a] += N[i][a];
            count[j] += 1;
        }
        for (std::size_t j = 0; j < n; ++j) {
            if (!fitted[j] || count[j] == 1) continue;
            const double len = std::sqrt(sum_n[j][0] * sum_n[j][0] + sum_n[j][1] * sum_n[j][1] + sum_n[j][2] * sum_n[j][2]);
            for (int a = 0; a < 3; ++a) fit_points[j][a] = sum_p[j][a] / count[j];
            if (len > 1e-9) for (int a = 0; a < 3; ++a) fit_normals[j][a] = sum_n[j][a] / len;
        }
    }

    // The local fits, in parallel (each leaf independent).
    m.leaves.resize(leaf_points.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaf_points.size(), 4), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t li = r.begin(); li < r.end(); ++li) {
            std::vector<std::uint32_t> idx = leaf_points[li];
            const std::size_t cap = 4 * std::size_t(options.leaf_min);  // a bounded solve, whatever the leaf
            if (idx.size() > cap) {
                std::vector<std::uint32_t> thin;
                for (std::size_t i = 0; i < cap; ++i) thin.push_back(idx[i * idx.size() / cap]);
                idx.swap(thin);
            }
            const Node& nd = m.nodes[std::size_t(leaf_nodes[li])];
            Leaf& leaf = m.leaves[li];
            for (int a = 0; a < 3; ++a) leaf.centre[a] = 0.5 * (nd.lo[a] + nd.hi[a]);
            leaf.scale = 0.5 * std::max({nd.hi[0] - nd.lo[0], nd.hi[1] - nd.lo[1], nd.hi[2] - nd.lo[2]});
            // On-surface constraints for every point; off-surface ones (+off and -off along
            // the normal, alternately) for every point too.
            const std::size_t k = idx.size();
            std::vector<Eigen::Vector3d> centres;
            std::vector<double> target;
            centres.reserve(2 * k);
            target.reserve(2 * k);
            const double d = off / leaf.scale;
            for (std::size_t i = 0; i < k; ++i) {
                const Vec3d& p = fit_points[idx[i]];
                centres.emplace_back((p[0] - leaf.centre[0]) / leaf.scale, (p[1] - leaf.centre[1]) / leaf.scale,
                                     (p[2] - leaf.centre[2]) / leaf.scale);
                target.push_back(0.0);
            }
            const std::size_t every = std::size_t(std::max(1, options.off_every));
            for (std::size_t i = 0; i < k; i += every) {
                const Vec3d& q = fit_normals[idx[i]];
                const double s = ((i / every) % 2 == 0) ? d : -d;
                centres.push_back(centres[i] + s * Eigen::Vector3d(q[0], q[1], q[2]));
                target.push_back(s);
            }
            const Eigen::Index c = Eigen::Index(centres.size());
            Eigen::MatrixXd A = Eigen::MatrixXd::Zero(c + 4, c + 4);
            Eigen::VectorXd b = Eigen::VectorXd::Zero(c + 4);
            for (Eigen::Index i = 0; i < c; ++i) {
                for (Eigen::Index j = 0; j < i; ++j) {
                    const double rr = (centres[std::size_t(i)] - centres[std::size_t(j)]).norm();
                    A(i, j) = A(j, i) = rr * rr * rr;
                }
                A(i, c) = A(c, i) = 1;
                for (int a = 0; a < 3; ++a) A(i, c + 1 + a) = A(c + 1 + a, i) = centres[std::size_t(i)][a];
                b[i] = target[std::size_t(i)];
            }
            Eigen::VectorXd lambda = A.partialPivLu().solve(b);
            if (!lambda.allFinite()) lambda = A.completeOrthogonalDecomposition().solve(b);
            for (Eigen::Index i = 0; i < c; ++i) {
                leaf.x.push_back(centres[std::size_t(i)].x());
                leaf.y.push_back(centres[std::size_t(i)].y());
                leaf.z.push_back(centres[std::size_t(i)].z());
                leaf.lambda.push_back(lambda[i]);
            }
            for (int a = 0; a < 4; ++a) leaf.poly[a] = lambda[c + a];
        }
    });
}

double RbfField::value(const Vec3d& p) const {
    double v = 0;
    impl_->values(&p, 1, &v);
    return v;
}

void RbfField::values(const std::vector<Vec3d>& points, std::vector<double>& out) const {
    out.resize(points.size());
    impl_->values(points.data(), points.size(), out.data());
}

Vec3d RbfField::gradient(const Vec3d& p) const {
    const double h = 0.25 * impl_->spacing;
    Vec3d g;
    for (int a = 0; a < 3; ++a) {
        Vec3d q = p, r = p;
        q[a] += h, r[a] -= h;
        g[a] = (value(q) - value(r)) / (2 * h);
    }
    return g;
}

Vec3d RbfField::box_min() const { return impl_->lo; }
Vec3d RbfField::box_max() const { return impl_->hi; }
std::size_t RbfField::leaves() const { return impl_->leaves.size(); }
double RbfField::spacing() const { return impl_->spacing; }
std::size_t RbfField::fitted_points() const { return impl_->fitted_points; }

double RbfField::distance_to_points(const Vec3d& p) const {
    double d2 = 0;
    impl_->tree->nearest(p, &d2);
    return std::sqrt(d2);
}

}  // namespace vdbmesh
