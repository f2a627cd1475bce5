// Label volumes put back after smoothing (restore_volumes.h).

#include "labels/restore_volumes.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace vdbmesh::labels_detail {
namespace {

constexpr int kNewtonSteps = 3;

Point sub(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Point cross(const Point& a, const Point& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// The vector area of a quad (normal from sides[0] to sides[1]), whatever its diagonal.
Point quad_area(const std::vector<Point>& p, const SheetQuad& q) {
    const Point c = cross(sub(p[q.vertex[2]], p[q.vertex[0]]), sub(p[q.vertex[3]], p[q.vertex[1]]));
    return {0.5 * c[0], 0.5 * c[1], 0.5 * c[2]};
}

/// Volume enclosed, per label value (below @a values), by its walls split as split_quads() splits them.
std::vector<double> label_volumes(const std::vector<Point>& p, const std::vector<SheetQuad>& quads, std::size_t values) {
    // Each quad's share in parallel, summed per label in quad order (the same sums for any thread count).
    std::vector<double> share(quads.size());
    tbb::parallel_for(std::size_t(0), quads.size(), [&](std::size_t i) {
        const auto& v = quads[i].vertex;
        const bool diagonal02 = dot(sub(p[v[0]], p[v[2]]), sub(p[v[0]], p[v[2]])) <= dot(sub(p[v[1]], p[v[3]]), sub(p[v[1]], p[v[3]]));
        const auto tet = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
            return dot(p[a], cross(p[b], p[c])) / 6;  // signed volume of (origin, a, b, c)
        };
        share[i] = diagonal02 ? tet(v[0], v[1], v[2]) + tet(v[0], v[2], v[3]) : tet(v[0], v[1], v[3]) + tet(v[1], v[2], v[3]);
    });
    std::vector<double> volume(values, 0.0);
    for (std::size_t i = 0; i < quads.size(); ++i) {
        volume[quads[i].sides[0]] += share[i];
        volume[quads[i].sides[1]] -= share[i];
    }
    return volume;
}

/// Per vertex, the quads round it (compressed rows).
struct VertexQuads {
    std::vector<std::uint32_t> start, list;
};

VertexQuads vertex_quads(std::size_t vertex_count, const std::vector<SheetQuad>& quads) {
    VertexQuads r;
    r.start.assign(vertex_count + 1, 0);
    for (const SheetQuad& q : quads)
        for (std::uint32_t v : q.vertex) ++r.start[v + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) r.start[v + 1] += r.start[v];
    r.list.resize(r.start.back());
    std::vector<std::uint32_t> fill(r.start.begin(), r.start.end() - 1);
    for (std::uint32_t i = 0; i < quads.size(); ++i)
        for (std::uint32_t v : quads[i].vertex) r.list[fill[v]++] = i;
    return r;
}

/// The gradients of the volumes of the labels round one vertex (at most the 8 round its corner).
class Gradients {
public:
    void add(int label, const Point& a, double sign) {
        if (label < 0) return;
        int i = 0;
        while (i < count_ && entries_[std::size_t(i)].first != label) ++i;
        if (i == count_) entries_[std::size_t(count_++)] = {label, {0, 0, 0}};
        for (int k = 0; k < 3; ++k) entries_[std::size_t(i)].second[k] += sign * 0.25 * a[k];
    }
    const std::pair<int, Point>* begin() const { return entries_.data(); }
    const std::pair<int, Point>* end() const { return entries_.data() + count_; }

private:
    std::array<std::pair<int, Point>, 8> entries_;
    int count_ = 0;
};

/// The gradients at vertex @a v of the volumes of the labels round it: a quarter of each
/// quad's vector area (@a areas, per quad; empty: all zero, for the labels alone), with the
/// sign of the side the label is on.
Gradients gradients(std::uint32_t v, const VertexQuads& round, const std::vector<SheetQuad>& quads, const std::vector<Point>& areas,
                    const std::vector<int>& index) {
    Gradients g;
    for (std::uint32_t i = round.start[v]; i < round.start[v + 1]; ++i) {
        const SheetQuad& q = quads[round.list[i]];
        const Point a = areas.empty() ? Point{0, 0, 0} : areas[round.list[i]];
        g.add(index[q.sides[0]], a, 1);
        g.add(index[q.sides[1]], a, -1);
    }
    return g;
}

/// One row of the Gram matrix: (column, value), by column.
using GramRow = std::vector<std::pair<int, double>>;

/// Per vertex (not frozen) the gradients of the volumes of the labels round it (compressed
/// rows; the labels round a vertex do not change, their gradients do).
struct VertexGradients {
    std::vector<std::uint32_t> start;
    std::vector<std::pair<int, Point>> list;
};

/// The Gram matrix of the labels' volume gradients, summed vertex by vertex in order
/// (deterministic), each row by column.
std::vector<GramRow> gram_matrix(const VertexGradients& g, std::size_t labels) {
    std::vector<GramRow> G(labels);
    for (std::size_t v = 0; v + 1 < g.start.size(); ++v)
        for (std::uint32_t i = g.start[v]; i < g.start[v + 1]; ++i) {
            GramRow& row = G[std::size_t(g.list[i].first)];
            for (std::uint32_t j = g.start[v]; j < g.start[v + 1]; ++j) {
                const int column = g.list[j].first;
                auto it = std::find_if(row.begin(), row.end(), [&](const auto& e) { return e.first == column; });
                if (it == row.end()) row.push_back({column, 0.0}), it = row.end() - 1;
                it->second += dot(g.list[i].second, g.list[j].second);
            }
        }
    for (GramRow& row : G) std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    return G;
}

/// Solves G x = b for the symmetric positive (semi)definite sparse G by conjugate gradients.
std::vector<double> solve(const std::vector<GramRow>& G, const std::vector<double>& b) {
    const std::size_t n = b.size();
    std::vector<double> x(n, 0), r = b, d = b, Gd(n);
    double rr = 0;
    for (double e : r) rr += e * e;
    const double stop = 1e-20 * std::max(rr, 1e-300);
    for (std::size_t it = 0; it < 4 * n + 16 && rr > stop; ++it) {
        for (std::size_t i = 0; i < n; ++i) {
            Gd[i] = 0;
            for (const auto& [j, value] : G[i]) Gd[i] += value * d[std::size_t(j)];
        }
        double dGd = 0;
        for (std::size_t i = 0; i < n; ++i) dGd += d[i] * Gd[i];
        if (!(dGd > 0)) break;
        const double alpha = rr / dGd;
        double next = 0;
        for (std::size_t i = 0; i < n; ++i) x[i] += alpha * d[i], r[i] -= alpha * Gd[i], next += r[i] * r[i];
        for (std::size_t i = 0; i < n; ++i) d[i] = r[i] + next / rr * d[i];
        rr = next;
    }
    return x;
}

}  // namespace

void restore_volumes(std::vector<Point>& place, const SheetVertices& vertices, const std::vector<SheetQuad>& quads,
                     const std::vector<std::uint64_t>& voxels, double max_offset, const std::vector<std::uint8_t>& frozen) {
    const auto is_frozen = [&](std::size_t v) { return !frozen.empty() && frozen[v]; };
    std::vector<int> index(voxels.size(), -1);
    std::vector<std::uint16_t> labels;
    for (std::size_t value = 1; value < voxels.size(); ++value)
        if (voxels[value]) index[value] = int(labels.size()), labels.push_back(std::uint16_t(value));
    if (labels.empty()) return;
    const VertexQuads round = vertex_quads(place.size(), quads);
    VertexGradients g;
    g.start.assign(place.size() + 1, 0);
    tbb::parallel_for(std::size_t(0), place.size(), [&](std::size_t v) {
        if (!is_frozen(v)) {
            const Gradients here = gradients(std::uint32_t(v), round, quads, {}, index);
            g.start[v + 1] = std::uint32_t(here.end() - here.begin());
        }
    });
    std::partial_sum(g.start.begin(), g.start.end(), g.start.begin());
    g.list.resize(g.start.back());
    // A label with no free vertex keeps its volume (its deficit would leave the system inconsistent).
    std::vector<std::uint8_t> movable(labels.size(), 0);
    tbb::parallel_for(std::size_t(0), place.size(), [&](std::size_t v) {
        if (g.start[v + 1] == g.start[v]) return;
        for (const auto& [label, gradient] : gradients(std::uint32_t(v), round, quads, {}, index)) movable[std::size_t(label)] = 1;
    });
    std::vector<Point> areas(quads.size()), next(place.size());  // per step, kept between steps
    for (int step = 0; step < kNewtonSteps; ++step) {
        const std::vector<double> volume = label_volumes(place, quads, voxels.size());
        std::vector<double> deficit(labels.size());
        for (std::size_t i = 0; i < labels.size(); ++i) deficit[i] = movable[i] ? double(voxels[labels[i]]) - volume[labels[i]] : 0.0;
        tbb::parallel_for(std::size_t(0), quads.size(), [&](std::size_t q) { areas[q] = quad_area(place, quads[q]); });
        tbb::parallel_for(std::size_t(0), place.size(), [&](std::size_t v) {
            if (g.start[v + 1] == g.start[v]) return;
            const Gradients here = gradients(std::uint32_t(v), round, quads, areas, index);
            std::copy(here.begin(), here.end(), g.list.begin() + g.start[v]);
        });
        const std::vector<double> lambda = solve(gram_matrix(g, labels.size()), deficit);
        tbb::parallel_for(std::size_t(0), place.size(), [&](std::size_t v) {
            Point move{0, 0, 0};
            if (is_frozen(v)) {
                next[v] = place[v];
                return;
            }
            for (std::uint32_t i = g.start[v]; i < g.start[v + 1]; ++i)
                for (int k = 0; k < 3; ++k) move[k] += lambda[std::size_t(g.list[i].first)] * g.list[i].second[k];
            for (int k = 0; k < 3; ++k)
                next[v][k] = std::clamp(place[v][k] + move[k], vertices.corner[v][k] - max_offset, vertices.corner[v][k] + max_offset);
        });
        place.swap(next);
    }
}

}  // namespace vdbmesh::labels_detail
