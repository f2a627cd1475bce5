// The Decimator's quadrics and edge costs (process/decimator.h): each vertex's quadric, where
// an edge's collapse puts the vertex and what it costs, refreshed as the triangles change; and
// the cheapest edges a round takes, the same for any thread count.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "process/decimator.h"

namespace vdbmesh::detail::decimation {

/// Ties of the quadric error (flat regions, where it is 0) go to the shorter edge, which keeps
/// the triangles there from growing into needles.
constexpr double kLengthWeight = 1e-3;

/// Each vertex's quadric: the planes of its triangles, summed around it.
void Decimator::gather_quadrics() {
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(positions_.size()), 4096), [&](const auto& range) {
        for (std::uint32_t v = range.begin(); v != range.end(); ++v) {
            if (vertex_corner_[v] == kNone) continue;
            around(v, [&](std::uint32_t c) {
                const Ids& t = triangles_[c / 3];
                const Vec3d n = normal(t);
                const double length = std::sqrt(dot(n, n));
                if (length == 0) return;
                quadrics_[v] = quadrics_[v] + Quadric::plane({n[0] / length, n[1] / length, n[2] / length}, point(t[0]));
            });
        }
    });
}

/// Where the collapse of (a, b), whose quadrics add up to @a q, puts the vertex, rounded to
/// floats: the quadric's minimizer when it is defined and near the edge, else the best of the
/// ends and the midpoint.
std::array<float, 3> Decimator::placement(const Quadric& q, std::uint32_t a, std::uint32_t b) const {
    const Vec3d pa = point(a), pb = point(b);
    const Vec3d mid{(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2};
    if (const auto best = q.minimizer()) {
        const Vec3d offset = sub(*best, mid), edge = sub(pb, pa);
        if (dot(offset, offset) <= dot(edge, edge)) return to_float(*best);
    }
    Vec3d chosen = mid;
    for (const Vec3d& p : {pa, pb}) {
        if (q.error(p) < q.error(chosen)) chosen = p;
    }
    return to_float(chosen);
}

/// Triangle @a t's box and the costs of its edges (each at the corner where it runs from the
/// lower vertex) but the one opposite corner @a unchanged (its ends have neither moved nor
/// merged: its cached cost holds); none of them refused any more.
void Decimator::refresh(std::uint32_t t, std::uint32_t unchanged) {
    boxes_[t] = empty_box();
    summaries_[t].facing = facing_directions(to_double(FloatTriangle{positions_[triangles_[t][0]], positions_[triangles_[t][1]], positions_[triangles_[t][2]]}));
    for (std::uint32_t c = 3 * t; c < 3 * t + 3; ++c) {
        grow(boxes_[t], positions_[vertex(c)]);
        rejected_[c] = 0;
        const std::uint32_t a = vertex(next(c)), b = vertex(prev(c));
        if (a > b) cost_[c] = kNever;
        if (a > b || c == unchanged) continue;
        const Quadric q = quadrics_[a] + quadrics_[b];
        position_[c] = placement(q, a, b);
        const double error = q.error(to_double(position_[c]));
        const Vec3d edge = sub(point(a), point(b));
        error_[c] = error;
        cost_[c] = error <= max_error_squared_ ? error + kLengthWeight * dot(edge, edge) : kNever;
    }
}

/// The edges that may collapse, at least the @a take cheapest of them (all, when fewer), in
/// the order of their corners; returns how many may collapse. Only those below a pivot are
/// kept as they are gathered: the same as all of them once sorted and cut, should at least
/// @a take fall below it (else all are gathered again).
std::size_t Decimator::gather_cheap(std::vector<Candidate>& candidates, std::size_t take) {
    const Candidate pivot = pivot_above(take);
    const std::size_t count = gather_below(pivot, candidates);
    if (candidates.size() < std::min(count, take) && pivot < kAboveAll) gather_below(kAboveAll, candidates);
    return count;
}

/// Of gather_cheap()'s @a candidates, the @a take cheapest in order of cost (a total order:
/// ties go by corner), whatever the thread count.
void Decimator::keep_cheapest(std::vector<Candidate>& candidates, std::size_t take) {
    sort_by_cost(candidates, sort_buffer_);
    if (candidates.size() > take) candidates.resize(take);
}

/// A candidate just above the @a take-th cheapest (most likely), from a regular sample of the
/// corners: four standard deviations of the sample's count and 3% high (the share itself is
/// estimated from the sample); none (above all) when they would be half or more.
Candidate Decimator::pivot_above(std::size_t take) const {
    constexpr std::size_t kSamples = 16384;
    const std::size_t corners = 3 * triangles_.size();
    std::vector<Candidate> sample;
    for (std::size_t i = 0; i < kSamples; ++i) {
        const auto c = std::uint32_t(i * corners / kSamples);
        if (alive_[c / 3] && collapsible(c)) sample.push_back({cost_[c], c});
    }
    const auto n = double(sample.size());
    const double share = double(take) / (n * double(corners) / double(kSamples));
    if (sample.empty() || share >= 0.5) return kAboveAll;
    const auto rank = std::size_t(share * n * 1.03 + 4 * std::sqrt(n * share * (1 - share))) + 1;
    if (rank >= sample.size()) return kAboveAll;
    std::nth_element(sample.begin(), sample.begin() + std::ptrdiff_t(rank), sample.end());
    return sample[rank];
}

/// The edges that may collapse whose candidates are below @a pivot, in the order of their
/// corners (whatever the thread count: each block of triangles is gathered on its own, then
/// the blocks are put end to end); returns how many may collapse in all.
std::size_t Decimator::gather_below(const Candidate& pivot, std::vector<Candidate>& candidates) {
    constexpr std::uint32_t kBlock = 16384;
    const auto triangles = std::uint32_t(triangles_.size());
    block_candidates_.resize((triangles + kBlock - 1) / kBlock);
    std::vector<std::size_t> counts(block_candidates_.size());
    tbb::parallel_for(std::size_t(0), block_candidates_.size(), [&](std::size_t block) {
        std::vector<Candidate>& found = block_candidates_[block];
        found.clear();
        std::size_t count = 0;
        for (auto t = std::uint32_t(block * kBlock); t < std::min(triangles, std::uint32_t((block + 1) * kBlock)); ++t) {
            if (!alive_[t]) continue;
            for (std::uint32_t c = 3 * t; c < 3 * t + 3; ++c) {
                if (!collapsible(c)) continue;
                ++count;
                if (const Candidate candidate{cost_[c], c}; candidate < pivot) found.push_back(candidate);
            }
        }
        counts[block] = count;
    });
    std::vector<std::size_t> offsets(block_candidates_.size() + 1, 0);
    for (std::size_t b = 0; b < block_candidates_.size(); ++b) offsets[b + 1] = offsets[b] + block_candidates_[b].size();
    candidates.resize(offsets.back());
    tbb::parallel_for(std::size_t(0), block_candidates_.size(), [&](std::size_t b) {
        std::copy(block_candidates_[b].begin(), block_candidates_[b].end(), candidates.begin() + std::ptrdiff_t(offsets[b]));
    });
    return std::accumulate(counts.begin(), counts.end(), std::size_t(0));
}

}  // namespace vdbmesh::detail::decimation
