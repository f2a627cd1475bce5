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
//    the fan's rim is positive, the quads' own triangles are positive, and the angles at v sum
//    to one turn, the projection is one-to-one on the star (a star-shaped polygon tiled by
//    positive triangles), so no two of its triangles meet beyond what they share. The signs
//    are taken with a relative margin of 1e-10, far above the rounding of the double
//    arithmetic on the float inputs, so a positive answer is exact; the angle sum is a whole
//    number of turns once every triangle is positive, so any total below three half-turns is one.
//  - Otherwise (several groups, or the certificate refused) every pair of its triangles gets
//    the exact tests of triangle_intersection.h.
// A pair found meeting sends the vertices of both triangles to their crossings' means, and
// the cells round them are proved again.

#include "mesh/dual_surface_proof.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

#include "geometry/triangle_intersection.h"
#include "mesh/dual_surface_groups.h"
#include "mesh/mc_table.h"
#include "mesh/mesh_phases.h"

namespace vdbmesh::detail {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSignMargin = 1e-10;
constexpr int kMaxRounds = 16;

Point3 sub(const Point3& a, const Point3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Point3& a, const Point3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Point3 cross(const Point3& a, const Point3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double norm(const Point3& a) { return std::sqrt(dot(a, a)); }

/// The cosine of the smallest angle of triangle abc (1 when degenerate).
double smallest_angle_cosine(const Point3& a, const Point3& b, const Point3& c) {
    const std::array<Point3, 3> corner = {a, b, c};
    double largest = -1;
    for (int k = 0; k < 3; ++k) {
        const Point3 u = sub(corner[(k + 1) % 3], corner[k]), w = sub(corner[(k + 2) % 3], corner[k]);
        const double lengths = norm(u) * norm(w);
        largest = std::max(largest, lengths > 0 ? dot(u, w) / lengths : 1.0);
    }
    return largest;
}

/// Sure that abc is positive seen along @a d: ((b - a) x (c - a)) . d above the margin.
bool surely_positive(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
    const Point3 u = sub(b, a), w = sub(c, a);
    return dot(cross(u, w), d) > kSignMargin * norm(u) * norm(w) * norm(d);
}

/// The angle at a of triangle abc projected along the unit vector @a d.
double projected_angle(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
    const Point3 u = sub(b, a), w = sub(c, a);
    return std::atan2(dot(cross(u, w), d), dot(u, w) - dot(u, d) * dot(w, d));
}

/// The quads round the crossed edges of one cell.
struct CellQuads {
    int count = 0;
    std::array<DualQuad, 12> quad;
};

CellQuads quads_round(const DualCells& cells, const DualPositions& positions, const openvdb::Coord& cell, unsigned config) {
    CellQuads quads;
    const CellGroups& groups = cell_groups(config);
    for (int e = 0; e < 12; ++e) {
        if (groups.of_edge[e] < 0) continue;
        const unsigned c = kEdgeCorners[e][0];
        quads.quad[quads.count++] = split_quad(cells, positions, cell.offsetBy(c & 1, (c >> 1) & 1, c >> 2), e / 4);
    }
    return quads;
}

/// The projection certificate for a cell whose every quad holds vertex @a v.
bool certified_star(const CellQuads& quads, std::uint32_t v, const std::vector<Point3>& at) {
    Point3 d = {0, 0, 0};
    for (int i = 0; i < quads.count; ++i) {
        for (const auto& t : quads.quad[i].triangles()) {
            const Point3 n = cross(sub(at[t[1]], at[t[0]]), sub(at[t[2]], at[t[0]]));
            for (int a = 0; a < 3; ++a) d[a] += n[a];
        }
    }
    const double length = norm(d);
    if (!(length > 0)) return false;
    for (double& x : d) x /= length;
    const Point3& p = at[v];
    double turn = 0;
    for (int i = 0; i < quads.count; ++i) {
        const DualQuad& quad = quads.quad[i];
        const int k = int(std::find(quad.vertex.begin(), quad.vertex.end(), v) - quad.vertex.begin());
        const Point3 &a = at[quad.vertex[(k + 1) % 4]], &b = at[quad.vertex[(k + 2) % 4]], &c = at[quad.vertex[(k + 3) % 4]];
        if (!surely_positive(p, a, b, d) || !surely_positive(p, b, c, d)) return false;
        const bool diagonal_through_v = quad.split_13 == (k % 2 == 1);
        if (!diagonal_through_v && (!surely_positive(p, a, c, d) || !surely_positive(a, b, c, d))) return false;
        turn += projected_angle(p, a, b, d) + projected_angle(p, b, c, d);
    }
    return turn < 3 * kPi;
}

Triangle3 corners(const std::array<std::uint32_t, 3>& t, const std::vector<Point3>& at) { return {at[t[0]], at[t[1]], at[t[2]]}; }

/// Whether two distinct triangles meet beyond the vertices they share (by index).
bool meet(const std::array<std::uint32_t, 3>& t, const std::array<std::uint32_t, 3>& u, const std::vector<Point3>& at) {
    std::array<int, 3> in_u;  // the corner of u each corner of t is, -1 when none
    int shared = 0;
    for (int i = 0; i < 3; ++i) {
        in_u[i] = int(std::find(u.begin(), u.end(), t[i]) - u.begin());
        if (in_u[i] == 3) in_u[i] = -1;
        shared += in_u[i] >= 0;
    }
    if (shared == 0) return triangles_meet(corners(t, at), corners(u, at));
    if (shared == 3) return true;  // the same triangle twice
    const int i = int(std::find_if(in_u.begin(), in_u.end(), [](int k) { return k >= 0; }) - in_u.begin());
    if (shared == 1) {
        const Triangle3 a = {at[t[i]], at[t[(i + 1) % 3]], at[t[(i + 2) % 3]]};
        const int j = in_u[i];
        const Triangle3 b = {at[u[j]], at[u[(j + 1) % 3]], at[u[(j + 2) % 3]]};
        return triangles_meet_beyond_corner(a, b);
    }
    const int lone_t = int(std::find(in_u.begin(), in_u.end(), -1) - in_u.begin());
    int lone_u = 0;
    while (std::find(t.begin(), t.end(), u[lone_u]) != t.end()) ++lone_u;
    return triangles_meet_beyond_edge(at[t[(lone_t + 1) % 3]], at[t[(lone_t + 2) % 3]], at[t[lone_t]], at[u[lone_u]]);
}

using FailedPair = std::array<std::uint32_t, 6>;

/// Every pair of the star's triangles that meets (a degenerate triangle: with itself).
void exact_tests(const CellQuads& quads, const std::vector<Point3>& at, std::vector<FailedPair>& failed, std::size_t& tested) {
    std::array<std::array<std::uint32_t, 3>, 24> triangles;
    int count = 0;
    for (int i = 0; i < quads.count; ++i)
        for (const auto& t : quads.quad[i].triangles()) triangles[count++] = t;
    for (int i = 0; i < count; ++i) {
        const auto& t = triangles[i];
        if (collinear(at[t[0]], at[t[1]], at[t[2]])) failed.push_back({t[0], t[1], t[2], t[0], t[1], t[2]});
        for (int j = i + 1; j < count; ++j) {
            ++tested;
            if (meet(t, triangles[j], at)) failed.push_back({t[0], t[1], t[2], triangles[j][0], triangles[j][1], triangles[j][2]});
        }
    }
}

/// Proves the stars of @a todo; returns the pairs found meeting, sorted.
std::vector<FailedPair> prove_cells(const DualCells& cells, const DualPositions& positions, const std::vector<openvdb::Coord>& todo,
                                    DualProofFigures& figures) {
    std::atomic<std::size_t> certified{0}, tested{0};
    std::vector<FailedPair> failed;
    std::mutex failed_mutex;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, todo.size(), 256), [&](const auto& range) {
        std::vector<FailedPair> mine;
        std::size_t my_certified = 0, my_tested = 0;
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const unsigned config = cells.config(todo[i]);
            const CellQuads quads = quads_round(cells, positions, todo[i], config);
            const CellGroups& groups = cell_groups(config);
            if (groups.count == 1) {
                const int edge = int(std::find_if(groups.of_edge.begin(), groups.of_edge.end(), [](std::int8_t g) { return g >= 0; }) - groups.of_edge.begin());
                if (certified_star(quads, cells.vertex(todo[i], edge), positions.at)) {
                    ++my_certified;
                    continue;
                }
            }
            exact_tests(quads, positions.at, mine, my_tested);
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

std::vector<openvdb::Coord> cells_with_surface(const DualCells& cells) {
    std::vector<openvdb::Coord> all;
    for (const DualBlock& block : cells.blocks()) {
        for (int i = 0; i < kDualBlockCells; ++i) {
            if (block.config[i] == 0 || block.config[i] == 255) continue;
            all.push_back(block.origin.offsetBy(i / (kBlockDim * kBlockDim), (i / kBlockDim) % kBlockDim, i % kBlockDim));
        }
    }
    return all;
}

/// The cells with surface within one cell of the cells holding @a vertices.
std::vector<openvdb::Coord> cells_round(const DualCells& cells, const std::vector<std::uint32_t>& vertices) {
    std::vector<openvdb::Coord> round;
    for (std::uint32_t v : vertices) {
        const openvdb::Coord centre = cells.cell_of_vertex(v);
        for (int n = 0; n < 27; ++n) {
            const openvdb::Coord cell = centre.offsetBy(n / 9 - 1, (n / 3) % 3 - 1, n % 3 - 1);
            const unsigned config = cells.config(cell);
            if (config != 0 && config != 255) round.push_back(cell);
        }
    }
    std::sort(round.begin(), round.end());
    round.erase(std::unique(round.begin(), round.end()), round.end());
    return round;
}

}  // namespace

DualQuad split_quad(const DualCells& cells, const DualPositions& positions, const openvdb::Coord& voxel, int axis) {
    DualQuad quad = cells.quad(voxel, axis);
    const auto& at = positions.at;
    const auto& v = quad.vertex;
    const double through_02 = std::max(smallest_angle_cosine(at[v[0]], at[v[1]], at[v[2]]), smallest_angle_cosine(at[v[0]], at[v[2]], at[v[3]]));
    const double through_13 = std::max(smallest_angle_cosine(at[v[0]], at[v[1]], at[v[3]]), smallest_angle_cosine(at[v[1]], at[v[2]], at[v[3]]));
    quad.split_13 = through_13 < through_02;
    return quad;
}

DualProofFigures prove_no_crossings(const DualCells& cells, DualPositions& positions, MeshReport& report) {
    PhaseClock clock;
    DualProofFigures figures;
    std::vector<openvdb::Coord> todo = cells_with_surface(cells);
    figures.cells = todo.size();
    std::vector<openvdb::Coord> stuck;  // cells holding a pair that no move can change
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
        for (std::uint32_t v : moved) {
            positions.at[v] = positions.mean[v];
            positions.at_mean[v] = true;
        }
        figures.moved += moved.size();
        const std::vector<openvdb::Coord> again = cells_round(cells, fixed);
        stuck.insert(stuck.end(), again.begin(), again.end());
        todo = cells_round(cells, moved);
        todo.insert(todo.end(), stuck.begin(), stuck.end());
        std::sort(todo.begin(), todo.end());
        todo.erase(std::unique(todo.begin(), todo.end()), todo.end());
    }
    return figures;
}

}  // namespace vdbmesh::detail
