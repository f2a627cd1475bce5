// The proof that the dual surface's triangles do not cross (dual_surface_proof.h).
//
// Why checking cell by cell is complete. Every vertex lies strictly inside its cell
// (kDualInteriorMargin, far above the float rounding of the written coordinates, on which
// every test below runs), so a quad's two triangles lie strictly inside the 2x2x1 block of
// cells round its grid edge. Two triangles that share a point therefore share a cell of their
// blocks, and both are among the triangles of the quads round that cell's crossed edges (its
// star). Proving, for every cell with surface, that no two triangles of its star meet beyond
// the vertices and edges they share proves it for the whole mesh.
//
// How a star is proved:
//  - A cell with one edge group has one vertex v, and its star is the fan of quads round v.
//    Projected along d (the sum of the star's area vectors), if every triangle (v, x, y) over
//    the fan's rim is positive, the quads' own triangles are positive, and the rim turns once
//    round v, the projection is one-to-one on the star (a star-shaped polygon tiled by
//    positive triangles), so no two of its triangles meet beyond what they share. The signs
//    are taken with a relative margin of 1e-10, far above the rounding of the double
//    arithmetic on the float inputs, so a positive answer is exact; the turns are counted as
//    the rim edges crossing a ray from v (each positive rim edge sweeps under a half-turn).
//  - Otherwise (several groups, or the certificate refused) every pair of its triangles gets
//    the exact tests of triangles_intersect() (geometry.h).
// A pair found meeting sends the vertices of both triangles to their crossings' means, and
// the cells round them are proved again.

#include "mesh/dual_surface_proof.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

#include "mesh/mesh_phases.h"

namespace vdbmesh::detail {

namespace {

constexpr double kSignMargin = 1e-10;
constexpr int kMaxRounds = 16;

Point3 sub(const Point3& a, const Point3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Point3& a, const Point3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Point3 cross(const Point3& a, const Point3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double norm(const Point3& a) { return std::sqrt(dot(a, a)); }

/// The signed square of the cosine of triangle abc's smallest angle (1 when degenerate): as
/// the cosine, larger for a smaller angle, without square roots.
double smallest_angle_signed_cosine2(const Point3& a, const Point3& b, const Point3& c) {
    const std::array<Point3, 3> corner = {a, b, c};
    double largest = -1;
    for (int k = 0; k < 3; ++k) {
        const Point3 u = sub(corner[(k + 1) % 3], corner[k]), w = sub(corner[(k + 2) % 3], corner[k]);
        const double lengths2 = dot(u, u) * dot(w, w), uw = dot(u, w);
        largest = std::max(largest, lengths2 > 0 ? uw * std::abs(uw) / lengths2 : 1.0);
    }
    return largest;
}

/// Sure that abc is positive seen along the unit vector @a d: ((b - a) x (c - a)) . d above the margin.
bool surely_positive(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
    const Point3 u = sub(b, a), w = sub(c, a);
    const double det = dot(cross(u, w), d);
    return det > 0 && det * det > kSignMargin * kSignMargin * dot(u, u) * dot(w, w);
}

/// Which side of the line through @a p along @a r (seen along @a d) @a x lies on: +1 left,
/// -1 right, 0 when too close to tell.
int side_of_ray(const Point3& p, const Point3& r, const Point3& x, const Point3& d) {
    const Point3 u = sub(x, p);
    const double s = dot(cross(r, u), d);
    if (s * s <= kSignMargin * kSignMargin * dot(r, r) * dot(u, u)) return 0;
    return s > 0 ? 1 : -1;
}

/// The quads of one cell's stars (the quads round its crossed edges).
struct CellQuads {
    int count = 0;
    std::array<std::uint32_t, 12> quad;
};

CellQuads quads_round(const DualCells& cells, const DualCellVertices& cell) {
    CellQuads quads;
    for (std::uint32_t v = cell.first; v < cell.first + cell.count; ++v)
        for (std::size_t s = cells.star_first(v); s < cells.star_first(v + 1); ++s) quads.quad[quads.count++] = cells.star_quads()[s];
    return quads;
}

/// The projection certificate for the star of @a v (the cell's only vertex).
bool certified_star(const DualCells& cells, const DualPositions& positions, const CellQuads& quads, std::uint32_t v) {
    const std::vector<Point3>& at = positions.at;
    Point3 d = {0, 0, 0};
    for (int i = 0; i < quads.count; ++i) {
        for (const auto& t : cells.quads()[quads.quad[i]].triangles(positions.split_13[quads.quad[i]])) {
            const Point3 n = cross(sub(at[t[1]], at[t[0]]), sub(at[t[2]], at[t[0]]));
            for (int a = 0; a < 3; ++a) d[a] += n[a];
        }
    }
    const double length = norm(d);
    if (!(length > 0)) return false;
    for (double& x : d) x /= length;
    // The rim's turns round v: every rim edge (x, y) with (v, x, y) positive sweeps less than a
    // half-turn counter-clockwise, so the turns are the rim edges crossing the ray from v
    // through the first rim vertex r0 from its right to its left (r0 itself counts as left).
    const Point3& p = at[v];
    const DualQuad& first = cells.quads()[quads.quad[0]];
    const std::uint32_t r0 = first.vertex[(std::find(first.vertex.begin(), first.vertex.end(), v) - first.vertex.begin() + 1) % 4];
    const Point3 ray = sub(at[r0], p);
    const auto side = [&](std::uint32_t x) { return x == r0 ? 1 : side_of_ray(p, ray, at[x], d); };
    int turns = 0;
    for (int i = 0; i < quads.count; ++i) {
        const DualQuad& quad = cells.quads()[quads.quad[i]];
        const int k = int(std::find(quad.vertex.begin(), quad.vertex.end(), v) - quad.vertex.begin());
        const std::uint32_t ia = quad.vertex[(k + 1) % 4], ib = quad.vertex[(k + 2) % 4], ic = quad.vertex[(k + 3) % 4];
        const Point3 &a = at[ia], &b = at[ib], &c = at[ic];
        if (!surely_positive(p, a, b, d) || !surely_positive(p, b, c, d)) return false;
        const bool diagonal_through_v = bool(positions.split_13[quads.quad[i]]) == (k % 2 == 1);
        if (!diagonal_through_v && (!surely_positive(p, a, c, d) || !surely_positive(a, b, c, d))) return false;
        const int sa = side(ia), sb = side(ib), sc = side(ic);
        if (sa == 0 || sb == 0 || sc == 0) return false;
        turns += (sa < 0 && sb > 0) + (sb < 0 && sc > 0);
    }
    return turns == 1;
}

Triangle3 corners(const std::array<std::uint32_t, 3>& t, const std::vector<Point3>& at) { return {at[t[0]], at[t[1]], at[t[2]]}; }

using FailedPair = std::array<std::uint32_t, 6>;

/// Every pair of the star's triangles that meets (a degenerate triangle: with itself).
void exact_tests(const DualCells& cells, const DualPositions& positions, const CellQuads& quads, std::vector<FailedPair>& failed,
                 std::size_t& tested) {
    const std::vector<Point3>& at = positions.at;
    std::array<std::array<std::uint32_t, 3>, 24> triangles;
    int count = 0;
    for (int i = 0; i < quads.count; ++i)
        for (const auto& t : cells.quads()[quads.quad[i]].triangles(positions.split_13[quads.quad[i]])) triangles[count++] = t;
    for (int i = 0; i < count; ++i) {
        const auto& t = triangles[i];
        if (collinear(at[t[0]], at[t[1]], at[t[2]])) failed.push_back({t[0], t[1], t[2], t[0], t[1], t[2]});
        for (int j = i + 1; j < count; ++j) {
            ++tested;
            if (triangles_intersect(t, corners(t, at), triangles[j], corners(triangles[j], at))) failed.push_back({t[0], t[1], t[2], triangles[j][0], triangles[j][1], triangles[j][2]});
        }
    }
}

/// Proves the stars of @a todo; returns the pairs found meeting, sorted.
std::vector<FailedPair> prove_cells(const DualCells& cells, const DualPositions& positions, const std::vector<DualCellVertices>& todo,
                                    DualProofFigures& figures) {
    std::atomic<std::size_t> certified{0}, tested{0};
    std::vector<FailedPair> failed;
    std::mutex failed_mutex;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, todo.size(), 256), [&](const auto& range) {
        std::vector<FailedPair> mine;
        std::size_t my_certified = 0, my_tested = 0;
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const CellQuads quads = quads_round(cells, todo[i]);
            if (todo[i].count == 1 && certified_star(cells, positions, quads, todo[i].first)) {
                ++my_certified;
                continue;
            }
            exact_tests(cells, positions, quads, mine, my_tested);
        }
        certified += my_certified;
        tested += my_tested;
        if (mine.empty()) return;
        std::lock_guard<std::mutex> lock(failed_mutex);
        failed.insert(failed.end(), mine.begin(), mine.end());
    });
    figures.certified += certified;
    figures.pairs_tested += tested;
    std::sort(failed.begin(), failed.end());
    failed.erase(std::unique(failed.begin(), failed.end()), failed.end());
    return failed;
}

/// The cells with surface within one cell of the cells holding @a vertices.
std::vector<DualCellVertices> cells_round(const DualCells& cells, const std::vector<std::uint32_t>& vertices) {
    std::vector<openvdb::Coord> round;
    for (std::uint32_t v : vertices) {
        const openvdb::Coord centre = cells.cell_of_vertex(v);
        for (int n = 0; n < 27; ++n) round.push_back(centre.offsetBy(n / 9 - 1, (n / 3) % 3 - 1, n % 3 - 1));
    }
    std::sort(round.begin(), round.end());
    round.erase(std::unique(round.begin(), round.end()), round.end());
    std::vector<DualCellVertices> found;
    for (const openvdb::Coord& cell : round) {
        const DualCellVertices vertices_of_cell = cells.cell_vertices(cell);
        if (vertices_of_cell.count > 0) found.push_back(vertices_of_cell);
    }
    return found;
}

/// The split of quad @a q whose triangles have the larger smallest angle.
bool split_13_is_better(const DualQuad& quad, const std::vector<Point3>& at) {
    const auto& v = quad.vertex;
    const double through_02 =
        std::max(smallest_angle_signed_cosine2(at[v[0]], at[v[1]], at[v[2]]), smallest_angle_signed_cosine2(at[v[0]], at[v[2]], at[v[3]]));
    const double through_13 =
        std::max(smallest_angle_signed_cosine2(at[v[0]], at[v[1]], at[v[3]]), smallest_angle_signed_cosine2(at[v[1]], at[v[2]], at[v[3]]));
    return through_13 < through_02;
}

/// Moves @a moved to their means and splits their quads again.
void move_to_means(const DualCells& cells, DualPositions& positions, const std::vector<std::uint32_t>& moved) {
    for (std::uint32_t v : moved) {
        positions.at[v] = positions.mean[v];
        positions.at_mean[v] = true;
    }
    for (std::uint32_t v : moved) {
        for (std::size_t s = cells.star_first(v); s < cells.star_first(v + 1); ++s) {
            const std::uint32_t q = cells.star_quads()[s];
            positions.split_13[q] = split_13_is_better(cells.quads()[q], positions.at);
        }
    }
}

}  // namespace

void choose_splits(const DualCells& cells, DualPositions& positions) {
    const std::vector<DualQuad>& quads = cells.quads();
    positions.split_13.resize(quads.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, quads.size(), 4096), [&](const auto& range) {
        for (std::size_t q = range.begin(); q != range.end(); ++q) positions.split_13[q] = split_13_is_better(quads[q], positions.at);
    });
}

DualProofFigures prove_no_crossings(const DualCells& cells, DualPositions& positions, MeshReport& report) {
    PhaseClock clock;
    DualProofFigures figures;
    std::vector<DualCellVertices> todo = cells.every_cell();
    figures.cells = todo.size();
    std::vector<DualCellVertices> stuck;  // cells holding a pair that no move can change
    while (!todo.empty()) {
        ++figures.rounds;
        const std::vector<FailedPair> failed = prove_cells(cells, positions, todo, figures);
        clock.lap(report, figures.rounds == 1 ? "proof" : "fallback");
        figures.pairs_failed += failed.size();
        std::vector<std::uint32_t> moved, fixed;
        for (const FailedPair& pair : failed) {
            bool movable = false;
            for (std::uint32_t v : pair) {
                if (positions.at_mean[v]) continue;
                movable = true;
                moved.push_back(v);
            }
            if (!movable) fixed.push_back(pair[0]);
        }
        std::sort(moved.begin(), moved.end());
        moved.erase(std::unique(moved.begin(), moved.end()), moved.end());
        if (moved.empty() || figures.rounds == kMaxRounds) {
            figures.unresolved = failed.size();
            break;
        }
        move_to_means(cells, positions, moved);
        figures.moved += moved.size();
        const std::vector<DualCellVertices> again = cells_round(cells, fixed);
        stuck.insert(stuck.end(), again.begin(), again.end());
        todo = cells_round(cells, moved);
        todo.insert(todo.end(), stuck.begin(), stuck.end());
        const auto by_first = [](const DualCellVertices& a, const DualCellVertices& b) { return a.first < b.first; };
        std::sort(todo.begin(), todo.end(), by_first);
        todo.erase(std::unique(todo.begin(), todo.end(), [](const DualCellVertices& a, const DualCellVertices& b) { return a.first == b.first; }), todo.end());
    }
    return figures;
}

}  // namespace vdbmesh::detail
