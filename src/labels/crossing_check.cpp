// The local exact crossing check (crossing_check.h).

#include "labels/crossing_check.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "vdbmesh/separating_plane.h"

namespace vdbmesh::labels_detail {
namespace {

using detail::Box;

Box merge(Box a, const Box& b) {
    for (int k = 0; k < 3; ++k) a.lo[k] = std::min(a.lo[k], b.lo[k]), a.hi[k] = std::max(a.hi[k], b.hi[k]);
    return a;
}

Box bounding_box(const std::vector<Box>& boxes) {
    if (boxes.empty()) return Box{{0, 0, 0}, {0, 0, 0}};
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, boxes.size()), boxes[0],
        [&](const tbb::blocked_range<std::size_t>& r, Box b) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) b = merge(b, boxes[i]);
            return b;
        },
        merge);
}

detail::Triangle3 corners(const Mesh& mesh, std::uint32_t t) {
    const auto& tri = mesh.triangles[t];
    detail::Triangle3 c;
    for (int i = 0; i < 3; ++i) c[i] = {mesh.vertices[tri[i]][0], mesh.vertices[tri[i]][1], mesh.vertices[tri[i]][2]};
    return c;
}

}  // namespace

/// The triangles found crossing, per thread.
struct CrossingCheck::Found {
    tbb::enumerable_thread_specific<std::vector<std::uint32_t>> lists;
    void add(std::uint32_t t, std::uint32_t u) {
        std::vector<std::uint32_t>& list = lists.local();
        list.push_back(t);
        list.push_back(u);
    }
};

/// Monotone in each coordinate: the cell of the larger of two points is the larger of their
/// cells, so two boxes that overlap both span the cell of the larger of their low corners.
/// Clamped to the grid (the boxes of later checks may leave the first one's bounds).
CrossingCheck::CellCoordinates CrossingCheck::coordinates(const std::array<float, 3>& p) const {
    CellCoordinates c;
    for (int k = 0; k < 3; ++k) c[k] = std::clamp(std::int32_t(std::floor((double(p[k]) - origin_[k]) * inverse_cell_)), 0, dims_[k] - 1);
    return c;
}

template <class Visit>
void CrossingCheck::for_each_cell(std::uint32_t t, Visit&& visit) const {
    for (std::int32_t z = lo_[t][2]; z <= hi_[t][2]; ++z)
        for (std::int32_t y = lo_[t][1]; y <= hi_[t][1]; ++y)
            for (std::int32_t x = lo_[t][0]; x <= hi_[t][0]; ++x) visit(index({x, y, z}));
}

void CrossingCheck::update(const Mesh& mesh, const std::vector<std::uint32_t>& triangles) {
    tbb::parallel_for(std::size_t(0), triangles.size(), [&](std::size_t i) {
        const std::uint32_t t = triangles[i];
        boxes_[t] = detail::triangle_box(mesh, t);
        const detail::Triangle3 c = corners(mesh, t);
        degenerate_[t] = detail::collinear(c[0], c[1], c[2]);
        if (!start_.empty()) lo_[t] = coordinates(boxes_[t].lo), hi_[t] = coordinates(boxes_[t].hi);
    });
}

void CrossingCheck::build_grid(const Mesh& mesh) {
    const std::size_t n = mesh.triangles.size();
    const Box bounds = bounding_box(boxes_);
    origin_ = {double(bounds.lo[0]), double(bounds.lo[1]), double(bounds.lo[2])};
    // Grown where the box is so wide that the grid would outnumber the triangles many times over.
    double cell = cell_;
    for (;; cell *= 2) {
        double cells = 1;
        for (int k = 0; k < 3; ++k) dims_[k] = std::int32_t(std::floor((double(bounds.hi[k]) - origin_[k]) / cell)) + 1, cells *= dims_[k];
        if (cells <= std::max(8.0 * double(n), double(1 << 20))) break;
    }
    inverse_cell_ = 1 / cell;
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t t) {
        lo_[t] = coordinates(boxes_[t].lo);
        hi_[t] = coordinates(boxes_[t].hi);
    });
    start_.assign(std::size_t(dims_[0]) * std::size_t(dims_[1]) * std::size_t(dims_[2]) + 1, 0);
    for (std::uint32_t t = 0; t < n; ++t) for_each_cell(t, [&](std::size_t c) { ++start_[c + 1]; });
    std::partial_sum(start_.begin(), start_.end(), start_.begin());
    list_.resize(start_.back());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::uint32_t t = 0; t < n; ++t) for_each_cell(t, [&](std::size_t c) { list_[fill[c]++] = t; });
}

/// Every pair, in the one cell holding the larger of their low corners' cells. A cell's
/// triangles are gathered (and prepared for the separating-plane proofs, which settle most
/// pairs before the exact predicates) once: its pairs read them many times.
void CrossingCheck::test_all(const Mesh& mesh, Found& found) const {
    struct Entry {
        detail::Box box;
        CellCoordinates lo;
        std::uint32_t triangle;
    };
    struct Gathered {
        std::vector<Entry> entries;
        std::vector<detail::PreparedTriangle> prepared;
    };
    tbb::enumerable_thread_specific<Gathered> gathered;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, start_.size() - 1, 256), [&](const tbb::blocked_range<std::size_t>& range) {
        Gathered& g = gathered.local();
        for (std::size_t c = range.begin(); c < range.end(); ++c) {
            if (start_[c + 1] - start_[c] < 2) continue;
            const CellCoordinates here{std::int32_t(c % std::size_t(dims_[0])), std::int32_t(c / std::size_t(dims_[0]) % std::size_t(dims_[1])),
                                       std::int32_t(c / std::size_t(dims_[0]) / std::size_t(dims_[1]))};
            g.entries.clear();
            g.prepared.clear();
            for (std::uint32_t i = start_[c]; i < start_[c + 1]; ++i) {
                const std::uint32_t t = list_[i];
                if (!degenerate_[t]) g.entries.push_back({boxes_[t], lo_[t], t}), g.prepared.emplace_back(corners(mesh, t));
            }
            for (std::size_t i = 0; i < g.entries.size(); ++i) {
                const Entry& t = g.entries[i];
                for (std::size_t j = i + 1; j < g.entries.size(); ++j) {
                    const Entry& u = g.entries[j];
                    if (!detail::boxes_overlap(t.box, u.box) || std::max(t.lo[0], u.lo[0]) != here[0] || std::max(t.lo[1], u.lo[1]) != here[1] ||
                        std::max(t.lo[2], u.lo[2]) != here[2])
                        continue;
                    if (detail::triangles_intersect(mesh.triangles[t.triangle], g.prepared[i], mesh.triangles[u.triangle], g.prepared[j]))
                        found.add(t.triangle, u.triangle);
                }
            }
        }
    });
}

/// The pairs of a moved triangle: with the unmoved ones through the first check's grid, with
/// the moved ones (this time or before) through an index of their cells now.
void CrossingCheck::test_moved(const Mesh& mesh, const std::vector<std::uint32_t>& moved, Found& found) {
    for (std::uint32_t t : moved)
        if (!moved_[t]) moved_[t] = 1, moved_list_.push_back(t);
    std::sort(moved_list_.begin(), moved_list_.end());
    std::vector<std::pair<std::size_t, std::uint32_t>> moved_cells;  // (cell, triangle), sorted
    for (std::uint32_t m : moved_list_) for_each_cell(m, [&](std::size_t c) { moved_cells.push_back({c, m}); });
    std::sort(moved_cells.begin(), moved_cells.end());
    std::vector<std::uint8_t> asked(boxes_.size(), 0);
    for (std::uint32_t t : moved) asked[t] = 1;
    tbb::parallel_for(std::size_t(0), moved.size(), [&](std::size_t i) {
        const std::uint32_t a = moved[i];
        if (degenerate_[a]) return;
        const detail::PreparedTriangle prepared(corners(mesh, a));
        const auto test = [&](std::uint32_t u, std::size_t c) {
            if (u == a || degenerate_[u] || !detail::boxes_overlap(boxes_[a], boxes_[u])) return;
            if (index({std::max(lo_[a][0], lo_[u][0]), std::max(lo_[a][1], lo_[u][1]), std::max(lo_[a][2], lo_[u][2])}) != c) return;
            if (detail::triangles_intersect(mesh.triangles[a], prepared, mesh.triangles[u], detail::PreparedTriangle(corners(mesh, u))))
                found.add(a, u);
        };
        for_each_cell(a, [&](std::size_t c) {
            for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k)
                if (!moved_[list_[k]]) test(list_[k], c);
            auto it = std::lower_bound(moved_cells.begin(), moved_cells.end(), std::pair<std::size_t, std::uint32_t>{c, 0});
            for (; it != moved_cells.end() && it->first == c; ++it)
                if (!(asked[it->second] && it->second < a)) test(it->second, c);  // a pair of two asked: once
        });
    });
}

std::vector<std::uint8_t> CrossingCheck::crossing_triangles(const Mesh& mesh, const std::vector<std::uint32_t>& moved) {
    const std::size_t n = mesh.triangles.size();
    Found found;
    std::vector<std::uint8_t> flagged(n, 0);
    if (start_.empty()) {
        boxes_.resize(n);
        lo_.resize(n);
        hi_.resize(n);
        degenerate_.resize(n);
        moved_.assign(n, 0);
        std::vector<std::uint32_t> all(n);
        std::iota(all.begin(), all.end(), 0u);
        update(mesh, all);
        build_grid(mesh);
        flagged = degenerate_;
        test_all(mesh, found);
    } else {
        update(mesh, moved);
        for (std::uint32_t t : moved) flagged[t] = degenerate_[t];
        test_moved(mesh, moved, found);
    }
    for (const auto& list : found.lists)
        for (std::uint32_t t : list) flagged[t] = 1;
    return flagged;
}

}  // namespace vdbmesh::labels_detail
