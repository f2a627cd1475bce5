#pragma once
// Private to the decimator (decimate_*.cpp): the Decimator that decimate_mesh() runs, its corner
// table and flat arrays, and what a round hands its checks. Its members are defined by job:
// decimate_corner_table.cpp (the table: linked, collapsed, read back), decimate_costs.cpp (the
// quadrics, the edges' costs, the cheapest edges), decimate_checks.cpp (one collapse's checks) and
// decimate_rounds.cpp (the rounds: the choice, the grids, the crossings, the apply); each
// member's comment is at its definition. The overview is at the top of decimate_mesh.cpp.

#include <tbb/enumerable_thread_specific.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "process/decimate_arrays.h"
#include "process/decimate_box_grid.h"
#include "process/decimate_candidates.h"
#include "process/decimate_facing.h"
#include "process/decimate_geometry.h"
#include "process/quadric.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/process.h"
#include "vdbmesh/separating_plane.h"

namespace vdbmesh::detail::decimation {

using Ids = std::array<std::uint32_t, 3>;
constexpr double kNever = std::numeric_limits<double>::infinity();  ///< the cost of an edge that may not collapse

inline std::uint32_t next(std::uint32_t c) { return c % 3 == 2 ? c - 2 : c + 1; }
inline std::uint32_t prev(std::uint32_t c) { return c % 3 == 0 ? c + 2 : c - 1; }

/// What the triangle grids hold of a triangle besides its box.
struct GridTriangle {
    std::uint32_t triangle;
    Summary summary;  ///< the directions it faces, its component
};

enum class Verdict : std::uint8_t { unchecked, passed, topology, geometry, intersection };

/// A collapse a round may make.
struct Plan {
    std::uint32_t corner = kNone;
    /// the corners round its ends, as the choice walked them: around[0] at the kept end, then
    /// around[1] at the other, from ring_begin in the round's ring corners
    std::uint32_t ring_begin = 0;
    std::array<std::uint32_t, 2> around{};
    Box star = empty_box();  ///< the box of the new star (once checked for crossings)
    Verdict verdict = Verdict::unchecked;
    std::vector<std::uint32_t> crossed;  ///< earlier passed plans of the round whose new stars cross this one's
    double volume_change = 0;            ///< (once passed) six times the change of the enclosed volume
    Box region = empty_box();            ///< (once passed) the box of the old and the new star
    Summary fan;                         ///< (once passed) the directions all its new triangles face, its component
    /// (once passed) the directions faced by its new triangles and all those meeting its region
    /// at the start of the round (none: its crossings were tested), its component
    Summary apart{0, kNone};
};

/// What the plan grid holds of a plan besides the box of its new star.
struct GridPlan {
    std::uint32_t plan;
    Summary summary;  ///< the plan's fan
};

/// A ring walk of choose_apart(): the corners round both ends of the edge opposite corner.
struct Walk {
    std::uint32_t corner;
    std::array<std::uint32_t, 2> at;  ///< where each walk is
    std::array<std::vector<std::uint32_t>, 2> around;
    /// where the walk round end 0 (the kept vertex) or 1 begins and ends: at the edge's own triangle
    std::uint32_t first(int end) const { return end == 0 ? next(corner) : prev(corner); }
};

/// Per-thread scratch of the checks.
struct Scratch {
    std::vector<std::uint8_t> mark;  ///< stamp per vertex (the choice's; a byte, so they keep to the nearer caches)
    std::uint8_t stamp = 0;
    std::vector<std::uint32_t> star;  ///< the triangles of the new star
    std::vector<Ids> ids;             ///< their corners' vertices after the collapse
    std::vector<detail::Triangle3> corners;
    std::vector<detail::PreparedTriangle> prepared;  ///< the corners with their planes (for the intersection tests)
    BoxColumns box_columns;                          ///< the boxes (for the intersection tests)
    std::vector<Box> boxes;
    std::vector<std::array<Vec3d, 2>> spokes;  ///< per star triangle, from the kept vertex to its other corners
    std::vector<Walk> walks;  ///< choose_apart()'s
    std::array<std::vector<std::uint32_t>, 2> neighbours;  ///< the neighbours of a plan's ends (link condition)
};

class Decimator {
public:
    Decimator(const Mesh& mesh, const DecimateOptions& options);

    /// Whether every edge has exactly two triangles, running either way, and every vertex one
    /// fan: the mesh is closed, manifold and oriented (what the decimation needs), found on the
    /// way to the corner table. When not, detail::analyze_topology() says what is wrong.
    bool closed_manifold() const { return closed_manifold_; }

    /// Collapses edges in rounds until the target is met or no edge may collapse; the mesh left.
    Mesh run(DecimateReport& report);

private:
    // ---- the corner table (decimate_corner_table.cpp): corner c is vertex c % 3 of triangle c / 3 ----

    std::uint32_t vertex(std::uint32_t c) const { return triangles_[c / 3][c % 3]; }

    /// The next corner at the same vertex (across the edge to vertex(next c)).
    std::uint32_t swing(std::uint32_t c) const { return prev(opposite_[prev(c)]); }

    /// Calls visit(corner) for each corner at @a v.
    template <class Visit>
    void around(std::uint32_t v, Visit&& visit) const {
        const std::uint32_t first = vertex_corner_[v];
        std::uint32_t c = first;
        do {
            visit(c);
            c = swing(c);
        } while (c != first);
    }

    bool link_corners();
    void measure_components();
    void apply(std::uint32_t corner, std::vector<std::uint32_t>& dirty);
    void name_opposite_corners(std::uint32_t corner);
    Mesh compact() const;

    // ---- quadrics, costs, the cheapest edges (decimate_costs.cpp) ----

    Vec3d point(std::uint32_t v) const { return to_double(positions_[v]); }
    Vec3d normal(const Ids& t) const { return cross(sub(point(t[1]), point(t[0])), sub(point(t[2]), point(t[0]))); }

    void gather_quadrics();
    std::array<float, 3> placement(const Quadric& q, std::uint32_t a, std::uint32_t b) const;
    void refresh(std::uint32_t t, std::uint32_t unchanged = kNone);
    std::size_t gather_cheap(std::vector<Candidate>& candidates, std::size_t take);
    void keep_cheapest(std::vector<Candidate>& candidates, std::size_t take);
    Candidate pivot_above(std::size_t take) const;
    std::size_t gather_below(const Candidate& pivot, std::vector<Candidate>& candidates);

    /// Whether the edge opposite corner @a c (of an alive triangle) may collapse now, seen from
    /// the corner where it runs from its lower vertex.
    bool collapsible(std::uint32_t c) const { return cost_[c] != kNever && !rejected_[c]; }

    // ---- a round (decimate_rounds.cpp) ----

    void choose_apart(const std::vector<Candidate>& candidates, std::vector<Plan>& plans, std::vector<std::uint32_t>& rings, Scratch& s) const;
    void walk_rings(Walk* walks, std::size_t size) const;
    void build_triangle_grids();
    void find_crossings(std::vector<Plan>& plans, const std::vector<std::uint32_t>& in_place,
                        tbb::enumerable_thread_specific<Scratch>& scratch);
    bool apart_from_all(const Plan& p) const;
    bool crosses_new_star(const Plan& q, const Box& star, const Scratch& s) const;
    void apply_round(const std::vector<Plan>& plans, DecimateReport& report);

    // ---- what the checks and the rounds both walk ----

    /// Calls visit(GridTriangle, box) for each alive triangle whose box meets @a box, until it returns
    /// false; returns whether it went through.
    template <class Visit>
    bool visit_triangles(const Box& box, Visit&& visit) const {
        if (moved_list_.empty()) return settled_grid_.visit(box, visit);  // (just rebuilt: none moved since)
        return settled_grid_.visit(box, [&](const GridTriangle& t, const Box& b) { return moved_[t.triangle] || visit(t, b); }) &&
               moved_grid_.visit(box, visit);
    }

    /// Calls visit(triangle) for each triangle round the ends of @a p (as the choice walked them).
    template <class Visit>
    void for_star(const Plan& p, Visit&& visit) const {
        const std::uint32_t* ring = ring_corners_.data() + p.ring_begin;
        for (std::uint32_t n = 0; n < p.around[0] + p.around[1]; ++n) visit(triangles_[ring[n] / 3]);
    }

    /// Calls visit(triangle, its vertices, their points, its box) for each triangle of @a p's
    /// new star (the triangles round its ends but the two on its edge, with b renamed a and a
    /// moved), from the corners the choice walked, until it returns false; returns whether it
    /// went through. The same while the round's collapses wait: the checks and the crossing
    /// tests see the same star.
    template <class Visit>
    bool for_new_star(const Plan& p, Visit&& visit) const {
        const std::uint32_t a = vertex(next(p.corner)), b = vertex(prev(p.corner));
        const std::array<float, 3>& position = position_[p.corner];
        const std::uint32_t t0 = p.corner / 3, t1 = opposite_[p.corner] / 3;
        const std::uint32_t* ring = ring_corners_.data() + p.ring_begin;
        for (std::uint32_t n = 0; n < p.around[0] + p.around[1]; ++n) {
            const std::uint32_t t = ring[n] / 3;
            if (t == t0 || t == t1) continue;
            Ids ids = triangles_[t];
            FloatTriangle points;
            Box box = empty_box();
            for (int k = 0; k < 3; ++k) {
                if (ids[k] == b) ids[k] = a;
                points[k] = ids[k] == a ? position : positions_[ids[k]];
                grow(box, points[k]);
            }
            if (!visit(t, ids, points, box)) return false;
        }
        return true;
    }

    FloatTriangle points_of(const Ids& t) const { return {positions_[t[0]], positions_[t[1]], positions_[t[2]]}; }

    // ---- one collapse's checks (decimate_checks.cpp) ----

    Verdict check(Plan& p, Scratch& s) const;
    bool linked_new_star(const Plan& p, Scratch& s) const;
    bool geometry_holds(const Scratch& s) const;
    bool star_is_a_graph(std::uint32_t a, Scratch& s) const;
    static void prepare_star(Scratch& s);
    bool intersection_free(Plan& p, Scratch& s) const;
    Slab slab_around(const Plan& p, const Scratch& s) const;
    double volume_change(const Plan& p, const Scratch& s) const;

    Array<std::array<float, 3>> positions_;
    Array<Ids> triangles_;
    Array<char> alive_;
    Array<std::uint32_t> opposite_;       ///< per corner
    Array<std::uint32_t> vertex_corner_;  ///< a corner at each vertex (kNone once removed)
    Array<Quadric> quadrics_;
    /// per corner, of the edge opposite it (from its lower vertex): the quadric error, and the
    /// cost (kNever at the corner where it runs from its higher vertex, or past the error bound)
    Array<double> cost_, error_;
    Array<std::array<float, 3>> position_;  ///< per corner: where that edge's collapse puts the vertex
    Array<char> rejected_;        ///< per corner: its edge's collapse failed a check since it last changed
    Array<Box> boxes_;            ///< per triangle
    Array<Summary> summaries_;    ///< per triangle: the directions it faces, its component
    std::vector<std::uint32_t> ring_corners_;  ///< the round's plans' corners round their ends (Plan::ring_begin)
    std::vector<std::uint32_t> dirty_;  ///< corners at the kept vertices of the round's collapses (their triangles to refresh)
    std::vector<std::vector<Candidate>> block_candidates_;  ///< gather_below() per block of triangles
    std::vector<Candidate> sort_buffer_;  ///< (sort_by_cost()'s, kept for its memory)
    Array<char> moved_;  ///< per triangle: changed (or removed) since settled_grid_ was built
    std::vector<std::uint32_t> moved_list_;  ///< those triangles (some removed since)
    std::vector<std::uint32_t> alive_list_;  ///< the alive triangles when settled_grid_ was built
    BoxGrid<GridTriangle> settled_grid_, moved_grid_;
    Box domain_ = empty_box();  ///< the box of the triangles when settled_grid_ was first built
    BoxGrid<GridPlan> plan_grid_;
    std::vector<double> volume_;            ///< per component: six times its enclosed volume
    std::size_t alive_count_;
    std::size_t target_;
    double max_error_squared_;
    bool closed_manifold_;
};

}  // namespace vdbmesh::detail::decimation
