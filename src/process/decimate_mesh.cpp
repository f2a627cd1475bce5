// decimate_mesh(): quadric edge collapse (M. Garland and P. Heckbert, SIGGRAPH 1997) that keeps a
// closed manifold mesh closed, manifold, oriented and free of self-intersections.
//
// The collapses are made in rounds. Each round takes the cheapest edges (about as many as
// collapses are still wanted) and picks among them, in order of cost, those whose ends lie in the
// star of no edge picked before (as meshoptimizer locks vertices). Those are checked in parallel
// against the mesh as it was at the start of the round, then applied in order of cost. No collapse
// of the round changes what another's checks read (its ends' rings, its star) but for the new
// triangles of two collapses: those crossings are found in parallel too, between the new stars as
// the checks built them, and a plan crossing one applied before it waits. So the result does not
// depend on the thread count. Each collapse is checked where it changes the mesh, on the float
// coordinates that will be written:
// - topology: the link condition (the ends' neighbours in common are exactly the two opposite
//   corners; T. K. Dey et al., "Topology preserving edge contraction", 1999), which keeps a
//   closed 2-manifold one;
// - geometry: no triangle of the new star is degenerate (exact collinearity) or turns by more
//   than kMaxTurnDegrees, and no component's enclosed volume changes sign (a nearly flat speck
//   can turn inside out while each triangle turns little; checked in the sequential apply, on
//   each component's volume kept up to date by the collapses' changes);
// - intersections: most collapses are cleared without a test between triangles, when all the
//   triangles near them and their new ones face a common direction (the proof is at
//   intersection_free()): the grids' cells keep what their triangles have in common. The others:
//   each new triangle against the others of the star and against the triangles the grids find
//   near it (one of all triangles, rebuilt once a quarter of them has moved, and one of those
//   moved since, rebuilt each round), with the exact tests of `vdbmesh check`; a plane that
//   certainly separates the two triangles (vdbmesh/separating_plane.h) spares most of them.
//   The same holds for the crossings between two new stars of a round.
// The mesh is held as a corner table (each corner's opposite corner across its edge), flat arrays
// throughout.
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

#include "process/decimate_arrays.h"
#include "process/decimate_box_grid.h"
#include "process/decimate_candidates.h"
#include "process/decimate_facing.h"
#include "process/decimate_geometry.h"
#include "process/quadric.h"
#include "vdbmesh/separating_plane.h"
#include "vdbmesh/error.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/process.h"
#include "vdbmesh/union_find.h"

namespace vdbmesh {
namespace {

using detail::Quadric;
using detail::Vec3d;
using Ids = std::array<std::uint32_t, 3>;
using detail::decimation::Array;
using detail::decimation::Box;
using detail::decimation::BoxColumns;
using detail::decimation::BoxGrid;
using detail::decimation::Candidate;
using detail::decimation::FloatTriangle;
using detail::decimation::Slab;
using detail::decimation::Summary;
using detail::decimation::cross;
using detail::decimation::dot;
using detail::decimation::empty_box;
using detail::decimation::facing_directions;
using detail::decimation::grow;
using detail::decimation::holds_nothing;
using detail::decimation::kAboveAll;
using detail::decimation::kNone;
using detail::decimation::parallel_array;
using detail::decimation::sort_by_cost;
using detail::decimation::sub;
using detail::decimation::to_double;
using detail::decimation::to_float;
constexpr double kMaxTurnDegrees = 75;  ///< largest change of a triangle's normal in one collapse
const double kMinTurnCosine = std::cos(kMaxTurnDegrees * 3.14159265358979323846 / 180);
/// Ties of the quadric error (flat regions, where it is 0) go to the shorter edge, which keeps
/// the triangles there from growing into needles.
constexpr double kLengthWeight = 1e-3;
constexpr double kNever = std::numeric_limits<double>::infinity();  ///< the cost of an edge that may not collapse
constexpr std::size_t kMinRound = 64;  ///< candidates a round takes at least
/// ... and at least this share of the triangles: near the target a round applies only about a
/// fifth of the few collapses still wanted, and every round costs passes over the whole mesh
/// (CThead: 38 rounds without, 19 with, the largest quadric error 1% higher).
constexpr std::size_t kMinRoundDivisor = 32;

std::uint32_t next(std::uint32_t c) { return c % 3 == 2 ? c - 2 : c + 1; }
std::uint32_t prev(std::uint32_t c) { return c % 3 == 0 ? c + 2 : c - 1; }

void check_closed_manifold(const Mesh& mesh) {
    const detail::Topology topology = detail::analyze_topology(mesh);
    if (topology.boundary_edges || topology.nonmanifold_edges || topology.nonmanifold_vertices || topology.misoriented_edges) {
        throw Error("decimate: expected a closed, manifold, consistently oriented mesh, got " +
                    std::to_string(topology.boundary_edges) + " boundary edges, " + std::to_string(topology.nonmanifold_edges) +
                    " non-manifold edges, " + std::to_string(topology.nonmanifold_vertices) + " non-manifold vertices, " +
                    std::to_string(topology.misoriented_edges) + " misoriented edges");
    }
}

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
    Decimator(const Mesh& mesh, const DecimateOptions& options)
        : positions_(parallel_array<std::array<float, 3>>(mesh.vertices.size(), [&](std::size_t v) { return mesh.vertices[v]; })),
          triangles_(parallel_array<Ids>(mesh.triangles.size(), [&](std::size_t t) { return mesh.triangles[t]; })),
          alive_(parallel_array<char>(mesh.triangles.size(), [](std::size_t) { return 1; })),
          opposite_(3 * mesh.triangles.size()),  // (link_corners() writes each, or fails)
          vertex_corner_(parallel_array<std::uint32_t>(mesh.vertices.size(), [](std::size_t) { return kNone; })),
          quadrics_(parallel_array<Quadric>(mesh.vertices.size(), [](std::size_t) { return Quadric{}; })),
          cost_(3 * mesh.triangles.size()), error_(3 * mesh.triangles.size()), position_(3 * mesh.triangles.size()),  // (refresh() writes them)
          rejected_(parallel_array<char>(3 * mesh.triangles.size(), [](std::size_t) { return 0; })),
          boxes_(mesh.triangles.size()),  // (refresh() writes each)
          summaries_(parallel_array<Summary>(mesh.triangles.size(), [](std::size_t) { return Summary{}; })),
          moved_(parallel_array<char>(mesh.triangles.size(), [](std::size_t) { return 0; })), alive_count_(mesh.triangles.size()),
          target_(options.target_triangles != 0 ? options.target_triangles
                                                : std::size_t(std::ceil(options.keep_fraction * double(mesh.triangles.size())))),
          max_error_squared_(options.max_error * options.max_error), closed_manifold_(link_corners()) {}

    /// Whether every edge has exactly two triangles, running either way, and every vertex one
    /// fan: the mesh is closed, manifold and oriented (what the decimation needs), found on the
    /// way to the corner table. When not, detail::analyze_topology() says what is wrong.
    bool closed_manifold() const { return closed_manifold_; }

    Mesh run(DecimateReport& report) {
        gather_quadrics();
        measure_components();
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(triangles_.size()), 4096), [&](const auto& range) {
            for (std::uint32_t t = range.begin(); t != range.end(); ++t) refresh(t);
        });
        tbb::enumerable_thread_specific<Scratch> scratch;
        std::vector<Candidate> candidates;
        std::vector<Plan> plans;
        Scratch own;
        own.mark.assign(positions_.size(), 0);
        while (alive_count_ > target_) {
            tbb::parallel_sort(dirty_.begin(), dirty_.end());  // (in memory order, as the checks below)
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, dirty_.size(), 1024), [&](const auto& range) {
                for (std::size_t i = range.begin(); i != range.end(); ++i) {
                    if (i + 8 < range.end()) {
                        const Ids& ahead = triangles_[dirty_[i + 8] / 3];
                        for (const std::uint32_t v : ahead) __builtin_prefetch(&quadrics_[v]), __builtin_prefetch(&quadrics_[v].d2), __builtin_prefetch(&positions_[v]);
                    }
                    refresh(dirty_[i] / 3, dirty_[i]);
                }
            });
            for (const std::uint32_t c : dirty_) {
                const std::uint32_t t = c / 3;
                if (!moved_[t]) moved_[t] = 1, moved_list_.push_back(t);
            }
            dirty_.clear();
            // The cheapest, about as many as the collapses still wanted (and never very few); with
            // under a quarter of the triangles to go, four times as many: about a third of them
            // are chosen and pass, so a round then makes about all the collapses wanted, where
            // as many would leave a tail of rounds that each pass over the whole mesh for a few
            // collapses (bunny: 16 rounds -> 14, 0.1 s of 3.8; the mean distance to the input +1%).
            const std::size_t collapses = (alive_count_ - target_ + 1) / 2;
            const std::size_t wanted = alive_count_ - target_ < alive_count_ / 4 ? 4 * collapses : collapses;
            const std::size_t take = std::max({kMinRound, wanted, alive_count_ / kMinRoundDivisor});
            if (gather_cheap(candidates, take) == 0) break;
            // The grids the checks read are built beside the sorting and the choice (mostly
            // sequential), which read neither them nor what building them writes.
            tbb::task_group grids;
            grids.run([&] { build_triangle_grids(); });
            keep_cheapest(candidates, take);
            choose_apart(candidates, plans, ring_corners_, own);
            grids.wait();
            // Checked in the order of their triangles, which keeps neighbours together in memory
            // (the checks are independent of each other; the cost order scatters them).
            std::vector<std::uint32_t> in_place(plans.size());
            for (std::uint32_t i = 0; i < plans.size(); ++i) in_place[i] = i;
            tbb::parallel_sort(in_place.begin(), in_place.end(), [&](std::uint32_t i, std::uint32_t j) { return plans[i].corner < plans[j].corner; });
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, plans.size(), 256), [&](const auto& range) {
                Scratch& s = scratch.local();
                for (std::size_t n = range.begin(); n != range.end(); ++n) {
                    // (in cost order the plans lie anywhere: each asked for 24 ahead, its star's
                    // triangles 16 ahead, their corners' points 8 ahead)
                    if (n + 24 < range.end()) __builtin_prefetch(&plans[in_place[n + 24]], 1);
                    if (n + 16 < range.end()) for_star(plans[in_place[n + 16]], [&](const Ids& t) { __builtin_prefetch(&t); });
                    if (n + 8 < range.end()) {
                        for_star(plans[in_place[n + 8]], [&](const Ids& t) {
                            for (const std::uint32_t v : t) __builtin_prefetch(&positions_[v]);
                        });
                    }
                    plans[in_place[n]].verdict = check(plans[in_place[n]], s);
                }
            });
            find_crossings(plans, in_place, scratch);
            apply_round(plans, report);
        }
        return compact();
    }

private:
    // ---- the corner table: corner c is vertex c % 3 of triangle c / 3 ----

    std::uint32_t vertex(std::uint32_t c) const { return triangles_[c / 3][c % 3]; }

    /// Each corner's opposite: the corner of the other triangle on the edge opposite it (that
    /// edge runs vertex(next c) -> vertex(prev c), and the other way in the other triangle).
    /// Returns closed_manifold().
    bool link_corners() {
        const std::size_t n = positions_.size();
        const auto corners = std::uint32_t(3 * triangles_.size());
        std::vector<std::uint32_t> start(n + 1, 0);
        for (std::uint32_t c = 0; c < corners; ++c) ++start[vertex(c) + 1];
        for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
        std::vector<std::uint32_t> at(start[n]);  // the corners at each vertex
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::uint32_t c = 0; c < corners; ++c) at[fill[vertex(c)]++] = c;
        // Round each vertex v: the edge from v to x, after its corner c, pairs with the edge from x
        // to v, before its corner d (both at v): the corners opposite them are prev(c) and next(d).
        std::atomic<bool> paired{true};
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
            for (std::size_t v = range.begin(); v != range.end(); ++v) {
                for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) {
                    const std::uint32_t c = at[i], x = vertex(next(c));
                    int found = 0;
                    for (std::uint32_t j = start[v]; j < start[v + 1]; ++j) {
                        if (vertex(prev(at[j])) == x) opposite_[prev(c)] = next(at[j]), ++found;
                    }
                    if (found != 1) paired = false;
                }
            }
        });
        for (std::uint32_t c = 0; c < corners; ++c) vertex_corner_[vertex(c)] = c;
        if (!paired) return false;
        // Each edge paired once (so opposite_ is an involution and every walk round a vertex
        // closes): a vertex is manifold when its walk meets all its corners.
        std::atomic<bool> fans{true};
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
            for (std::size_t v = range.begin(); v != range.end(); ++v) {
                if (start[v] == start[v + 1]) continue;
                std::uint32_t count = 0;
                around(std::uint32_t(v), [&](std::uint32_t) { ++count; });
                if (count != start[v + 1] - start[v]) fans = false;
            }
        });
        return fans;
    }

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

    // ---- quadrics, costs, boxes ----

    Vec3d point(std::uint32_t v) const { return to_double(positions_[v]); }
    Vec3d normal(const Ids& t) const { return cross(sub(point(t[1]), point(t[0])), sub(point(t[2]), point(t[0]))); }

    /// Each vertex's quadric: the planes of its triangles, summed around it.
    void gather_quadrics() {
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
    std::array<float, 3> placement(const Quadric& q, std::uint32_t a, std::uint32_t b) const {
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
    void refresh(std::uint32_t t, std::uint32_t unchanged = kNone) {
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

    /// Whether the edge opposite corner @a c (of an alive triangle) may collapse now, seen from
    /// the corner where it runs from its lower vertex.
    bool collapsible(std::uint32_t c) const { return cost_[c] != kNever && !rejected_[c]; }

    /// The edges that may collapse, at least the @a take cheapest of them (all, when fewer), in
    /// the order of their corners; returns how many may collapse. Only those below a pivot are
    /// kept as they are gathered: the same as all of them once sorted and cut, should at least
    /// @a take fall below it (else all are gathered again).
    std::size_t gather_cheap(std::vector<Candidate>& candidates, std::size_t take) {
        const Candidate pivot = pivot_above(take);
        const std::size_t count = gather_below(pivot, candidates);
        if (candidates.size() < std::min(count, take) && pivot < kAboveAll) gather_below(kAboveAll, candidates);
        return count;
    }

    /// Of gather_cheap()'s @a candidates, the @a take cheapest in order of cost (a total order:
    /// ties go by corner), whatever the thread count.
    void keep_cheapest(std::vector<Candidate>& candidates, std::size_t take) {
        sort_by_cost(candidates, sort_buffer_);
        if (candidates.size() > take) candidates.resize(take);
    }

    /// A candidate just above the @a take-th cheapest (most likely), from a regular sample of the
    /// corners: four standard deviations of the sample's count and 3% high (the share itself is
    /// estimated from the sample); none (above all) when they would be half or more.
    Candidate pivot_above(std::size_t take) const {
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
    std::size_t gather_below(const Candidate& pivot, std::vector<Candidate>& candidates) {
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

    // ---- a round ----

    /// The candidates, in order of cost, whose ends lie in the star of no earlier one chosen.
    /// Then no collapse of the round changes the rings of another's ends or the triangles of its
    /// star (a triangle changes only if it has an end of the collapse, and a vertex's ring only
    /// if it is in the star), which is what the link condition and the geometry check read.
    /// Each plan's corners round its ends go to @a rings (the checks read them from there without
    /// walking the rings again, a chain of loads). The rings are walked a batch of candidates at a
    /// time, side by side (many chains of loads in flight, not one): the next ones whose ends no
    /// earlier choice has marked, then chosen in order as before (one may yet be marked by one
    /// chosen before it in the batch; its walk is then wasted).
    void choose_apart(const std::vector<Candidate>& candidates, std::vector<Plan>& plans, std::vector<std::uint32_t>& rings, Scratch& s) const {
        plans.clear(), rings.clear();
        if (++s.stamp == 0) std::fill(s.mark.begin(), s.mark.end(), 0), s.stamp = 1;
        const std::uint8_t stamp = s.stamp;
        const auto marked = [&](std::uint32_t corner) { return s.mark[vertex(next(corner))] == stamp || s.mark[vertex(prev(corner))] == stamp; };
        constexpr std::size_t kBatch = 32;
        s.walks.resize(kBatch);
        for (std::size_t n = 0; n < candidates.size();) {
            std::size_t size = 0;
            for (; n < candidates.size() && size < kBatch; ++n) {
                // (in cost order the candidates lie anywhere: their triangles and those triangles'
                // opposite corners asked for 16 ahead, then their ends' marks 8 ahead)
                if (n + 16 < candidates.size()) {
                    const std::uint32_t ahead = candidates[n + 16].corner;
                    __builtin_prefetch(&triangles_[ahead / 3]), __builtin_prefetch(&opposite_[ahead - ahead % 3]);
                }
                if (n + 8 < candidates.size()) {
                    const std::uint32_t ahead = candidates[n + 8].corner;
                    for (const std::uint32_t v : {vertex(next(ahead)), vertex(prev(ahead))}) __builtin_prefetch(&s.mark[v]);
                }
                if (!marked(candidates[n].corner)) s.walks[size++].corner = candidates[n].corner;
            }
            walk_rings(s.walks.data(), size);
            for (std::size_t k = 0; k < size; ++k) {
                const Walk& walk = s.walks[k];
                if (marked(walk.corner)) continue;
                Plan plan;
                plan.corner = walk.corner;
                plan.ring_begin = std::uint32_t(rings.size());
                for (int end = 0; end < 2; ++end) {
                    plan.around[end] = std::uint32_t(walk.around[end].size());
                    for (const std::uint32_t c : walk.around[end]) s.mark[vertex(next(c))] = stamp, rings.push_back(c);
                }
                plans.push_back(plan);
            }
        }
    }

    /// The corners round both ends of each of @a walks, from the edge's own triangle, all walked
    /// side by side.
    void walk_rings(Walk* walks, std::size_t size) const {
        std::size_t walking = 0;
        for (std::size_t k = 0; k < size; ++k) {
            Walk& walk = walks[k];
            for (int end = 0; end < 2; ++end) walk.around[end].clear(), walk.at[end] = walk.first(end);
            walking += 2;
        }
        while (walking > 0) {
            for (std::size_t k = 0; k < size; ++k) {
                Walk& walk = walks[k];
                for (int end = 0; end < 2; ++end) {
                    std::vector<std::uint32_t>& around = walk.around[end];
                    if (!around.empty() && walk.at[end] == walk.first(end)) continue;
                    around.push_back(walk.at[end]);
                    __builtin_prefetch(&triangles_[walk.at[end] / 3]);  // (its neighbour is marked once chosen)
                    walk.at[end] = swing(walk.at[end]);
                    walking -= walk.at[end] == walk.first(end);
                }
            }
        }
    }

    /// For each plan that passed its checks, the earlier ones that did too and whose new stars
    /// cross its own: no plan's ends are in another's star, so each check still holds but for
    /// the new triangles of two collapses of the round, which no check has met. Both new stars
    /// are as the checks built them from the mesh at the start of the round: no other collapse
    /// of the round changes them (their vertices are neither collapse's ends nor its ends'
    /// neighbours; two stars may share link vertices, which the exact tests allow for).
    /// @a in_place: the plans in the order to visit them (any order gives the same crossings).
    void find_crossings(std::vector<Plan>& plans, const std::vector<std::uint32_t>& in_place,
                        tbb::enumerable_thread_specific<Scratch>& scratch) {
        plan_grid_.build(
            plans.size(), [&](std::size_t i) { return plans[i].verdict == Verdict::passed ? plans[i].star : empty_box(); },
            [&](std::size_t i) { return GridPlan{std::uint32_t(i), plans[i].fan}; });
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, in_place.size(), 64), [&](const auto& range) {
            Scratch& s = scratch.local();
            for (std::size_t n = range.begin(); n != range.end(); ++n) {
                if (n + 8 < range.end()) __builtin_prefetch(&plans[in_place[n + 8]]);  // (in cost order: anywhere)
                const std::uint32_t i = in_place[n];
                Plan& p = plans[i];
                if (p.verdict != Verdict::passed) continue;
                p.crossed.clear();
                if (apart_from_all(p)) continue;
                bool star_ready = false;
                plan_grid_.visit(p.star, [&](const GridPlan& entry, const Box&) {
                    const std::uint32_t j = entry.plan;
                    if (j >= i) return true;
                    if (!star_ready) {
                        s.ids.clear(), s.corners.clear(), s.boxes.clear();
                        for_new_star(p, [&](std::uint32_t, const Ids& ids, const FloatTriangle& points, const Box& box) {
                            s.ids.push_back(ids), s.corners.push_back(to_double(points)), s.boxes.push_back(box);
                            return true;
                        });
                        prepare_star(s);
                        star_ready = true;
                    }
                    if (crosses_new_star(plans[j], p.star, s)) p.crossed.push_back(j);
                    return true;
                });
            }
        });
    }

    /// Applies the plans that passed their checks, in order of cost, while triangles are to go;
    /// a plan whose new star crosses that of one applied before waits for the next round. The
    /// cost order decides which apply; they are then applied in the order of their triangles
    /// (neighbours together in memory), side by side: their stars share no triangle, so no
    /// collapse reads or writes what another writes but vertex_corner_ at a link vertex two
    /// stars share, which is set after, in that order.
    void apply_round(const std::vector<Plan>& plans, DecimateReport& report) {
        std::vector<char> applied(plans.size(), 0);
        std::vector<std::uint32_t> chosen;
        std::size_t alive = alive_count_;
        for (std::uint32_t i = 0; i < plans.size() && alive > target_; ++i) {
            const Plan& p = plans[i];
            if (p.verdict != Verdict::passed) {
                rejected_[p.corner] = 1;
                ++(p.verdict == Verdict::topology ? report.rejected_topology
                   : p.verdict == Verdict::geometry ? report.rejected_geometry
                                                    : report.rejected_intersection);
                continue;
            }
            if (std::any_of(p.crossed.begin(), p.crossed.end(), [&](std::uint32_t j) { return applied[j] != 0; })) continue;
            double& volume = volume_[p.fan.component];
            if (volume != 0 && (volume + p.volume_change) * volume <= 0) {  // the component would turn inside out
                rejected_[p.corner] = 1;
                ++report.rejected_geometry;
                continue;
            }
            volume += p.volume_change;
            applied[i] = 1;
            chosen.push_back(p.corner);
            alive -= 2;
        }
        tbb::parallel_sort(chosen.begin(), chosen.end());
        tbb::enumerable_thread_specific<std::vector<std::uint32_t>> dirty;
        tbb::enumerable_thread_specific<double> max_error(0.0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chosen.size(), 256), [&](const auto& range) {
            std::vector<std::uint32_t>& local = dirty.local();
            double& largest = max_error.local();
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                largest = std::max(largest, error_[chosen[i]]);
                if (i + 8 < range.end()) {  // (the ends' quadrics are read at random)
                    const std::uint32_t ahead = chosen[i + 8];
                    for (const std::uint32_t v : {vertex(next(ahead)), vertex(prev(ahead))}) __builtin_prefetch(&quadrics_[v], 1), __builtin_prefetch(&vertex_corner_[v], 1);
                }
                apply(chosen[i], local);
            }
        });
        for (const std::uint32_t corner : chosen) name_opposite_corners(corner);
        for (const double error : max_error) report.max_error = std::max(report.max_error, std::sqrt(error));
        report.collapses += chosen.size();
        alive_count_ -= 2 * chosen.size();
        for (const std::vector<std::uint32_t>& local : dirty) dirty_.insert(dirty_.end(), local.begin(), local.end());  // (sorted before use)
    }

    /// Whether @a p's new star certainly crosses no other of the round, whichever of them apply
    /// before it: the directions its check found faced in its region are also faced by the new
    /// stars of all passed plans near it, of its component (so the mesh as it is when p applies,
    /// the round's start but for those stars, meets intersection_free()'s condition). The plan
    /// grid's cells tell first what the stars in them have in common; failing that, the stars met.
    bool apart_from_all(const Plan& p) const {
        if (!p.apart.clears()) return false;
        Summary in_cells = p.apart;
        in_cells.add(plan_grid_.summary(p.region));
        if (in_cells.clears()) return true;
        Summary met = p.apart;
        plan_grid_.visit(p.region, [&](const GridPlan& q, const Box&) { return met.add(q.summary), met.clears(); });
        return met.clears();
    }

    /// Whether a triangle of the new star in @a s (whose box is @a star) crosses one of the new
    /// star of plan @a q (neither holds the other's kept vertex).
    bool crosses_new_star(const Plan& q, const Box& star, const Scratch& s) const {
        return !for_new_star(q, [&](std::uint32_t, const Ids& ids, const FloatTriangle& points, const Box& box) {
            if (!detail::boxes_overlap(star, box)) return true;
            const detail::PreparedTriangle corners(to_double(points));
            return s.box_columns.for_meeting(box, [&](std::size_t i) { return !detail::triangles_intersect(s.ids[i], s.prepared[i], ids, corners); });
        });
    }

    /// The alive triangles with their boxes, in cells of kCellEdges mean extents: those that
    /// moved since the settled grid was built in a grid of their own, rebuilt each round; the
    /// settled grid rebuilt only once a quarter of the triangles has moved.
    void build_triangle_grids() {
        const auto dead = [&](std::uint32_t t) { return alive_[t] == 0; };
        const bool all = settled_grid_.empty() || moved_list_.size() > alive_count_ / 4;
        if (all) {
            for (const std::uint32_t t : moved_list_) moved_[t] = 0;
            moved_list_.clear();
            if (alive_list_.empty()) alive_list_.resize(triangles_.size()), std::iota(alive_list_.begin(), alive_list_.end(), 0u);
            alive_list_.erase(std::remove_if(alive_list_.begin(), alive_list_.end(), dead), alive_list_.end());
        } else {
            moved_list_.erase(std::remove_if(moved_list_.begin(), moved_list_.end(), dead), moved_list_.end());
        }
        const std::vector<std::uint32_t>& ids = all ? alive_list_ : moved_list_;
        const auto box_of = [&](std::size_t i) { return boxes_[ids[i]]; };
        const auto payload_of = [&](std::size_t i) { return GridTriangle{ids[i], summaries_[ids[i]]}; };
        if (!all) {
            moved_grid_.build(ids.size(), box_of, payload_of);
            return;
        }
        // (the settled grid over the box of the first triangles: the collapses keep to it but by
        // a little, and the pass over all boxes for theirs is spared)
        if (holds_nothing(domain_)) {
            for (std::size_t i = 0; i < ids.size(); ++i) grow(domain_, box_of(i).lo), grow(domain_, box_of(i).hi);
        }
        settled_grid_.build(ids.size(), box_of, payload_of, &domain_);
        moved_grid_.build(0, [](std::size_t) { return empty_box(); }, [](std::size_t) { return GridTriangle{}; });
    }

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

    /// Whether the edge of @a p meets the link condition (its ends' neighbours in common are only
    /// the two opposite corners; the kept vertex keeps three neighbours at least), and its new
    /// star in @a s (for_new_star(): its triangles, their corners as doubles, their boxes).
    bool linked_new_star(const Plan& p, Scratch& s) const {
        if (vertex(p.corner) == vertex(opposite_[p.corner])) return false;
        s.star.clear(), s.ids.clear(), s.corners.clear(), s.boxes.clear();
        for_new_star(p, [&](std::uint32_t t, const Ids& ids, const FloatTriangle& points, const Box& box) {
            s.star.push_back(t), s.ids.push_back(ids), s.corners.push_back(to_double(points)), s.boxes.push_back(box);
            return true;
        });
        const std::uint32_t* ring = ring_corners_.data() + p.ring_begin;
        for (const int end : {0, 1}) {
            const std::uint32_t* corners = end == 0 ? ring : ring + p.around[0];
            std::vector<std::uint32_t>& neighbours = s.neighbours[end];
            neighbours.clear();
            for (std::uint32_t n = 0; n < p.around[end]; ++n) neighbours.push_back(vertex(next(corners[n])));
            std::sort(neighbours.begin(), neighbours.end());
        }
        std::size_t common = 0;
        for (auto i = s.neighbours[0].begin(), j = s.neighbours[1].begin(); i != s.neighbours[0].end() && j != s.neighbours[1].end();) {
            if (*i == *j) ++common, ++i, ++j;
            else if (*i < *j) ++i;
            else ++j;
        }
        return common == 2 && p.around[0] + p.around[1] >= 4 + 3;
    }

    bool geometry_holds(const Scratch& s) const {
        for (std::size_t i = 0; i < s.star.size(); ++i) {
            const detail::Triangle3& c = s.corners[i];
            if (detail::collinear(c[0], c[1], c[2])) return false;
            const Vec3d before = normal(triangles_[s.star[i]]), after = cross(sub(c[1], c[0]), sub(c[2], c[0]));
            if (dot(before, after) < kMinTurnCosine * std::sqrt(dot(before, before) * dot(after, after))) return false;
        }
        return true;
    }

    /// Whether the new star (a closed fan around the kept vertex @a a) is certainly free of
    /// crossings among its triangles: seen along one direction, each turns the same way (exact
    /// orientations) and their angles at the kept vertex add up to one turn (the sum is a whole
    /// number of turns, so rounding cannot mislead), so the fan projects one-to-one onto a plane.
    bool star_is_a_graph(std::uint32_t a, Scratch& s) const {
        std::vector<std::array<Vec3d, 2>>& spokes = s.spokes;
        spokes.resize(s.star.size());
        Vec3d n{0, 0, 0};
        double reach = 0;
        for (std::size_t i = 0; i < s.star.size(); ++i) {
            const int k = s.ids[i][0] == a ? 0 : s.ids[i][1] == a ? 1 : 2;
            spokes[i] = {sub(s.corners[i][(k + 1) % 3], s.corners[i][k]), sub(s.corners[i][(k + 2) % 3], s.corners[i][k])};
            const Vec3d c = cross(spokes[i][0], spokes[i][1]);
            for (int j = 0; j < 3; ++j) n[j] += c[j];
            reach = std::max(reach, dot(spokes[i][0], spokes[i][0]));
        }
        const double length = std::sqrt(dot(n, n));
        if (!(length > 0)) return false;
        const Vec3d& p = s.corners[0][s.ids[0][0] == a ? 0 : s.ids[0][1] == a ? 1 : 2];
        const double scale = std::sqrt(reach) / length;
        const Vec3d q{p[0] + n[0] * scale, p[1] + n[1] * scale, p[2] + n[2] * scale};
        // A basis of the plane across n, for the angles.
        const Vec3d d{n[0] / length, n[1] / length, n[2] / length};
        const Vec3d helper = std::abs(d[0]) < 0.6 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
        Vec3d u = cross(d, helper);
        const double u_length = std::sqrt(dot(u, u));
        u = {u[0] / u_length, u[1] / u_length, u[2] / u_length};
        const Vec3d v = cross(d, u);
        int turn = 0;
        double angles = 0;
        for (std::size_t i = 0; i < s.star.size(); ++i) {
            const int k = s.ids[i][0] == a ? 0 : s.ids[i][1] == a ? 1 : 2;
            const int sign = detail::orient3d(s.corners[i][k], s.corners[i][(k + 1) % 3], s.corners[i][(k + 2) % 3], q);
            if (sign == 0 || (turn != 0 && sign != turn)) return false;
            turn = sign;
            const double x1 = dot(spokes[i][0], u), y1 = dot(spokes[i][0], v), x2 = dot(spokes[i][1], u), y2 = dot(spokes[i][1], v);
            angles += std::atan2(std::abs(x1 * y2 - x2 * y1), x1 * x2 + y1 * y2);
        }
        return angles < 3 * 3.14159265358979323846;
    }

    /// s.prepared and s.box_columns from s.corners and s.boxes.
    static void prepare_star(Scratch& s) {
        s.prepared.clear();
        for (const detail::Triangle3& t : s.corners) s.prepared.emplace_back(t);
        s.box_columns.assign(s.boxes);
    }

    /// The new triangles cross neither each other nor any triangle near them off the old star.
    ///
    /// Most collapses are settled without a test between triangles: the new star crosses
    /// nothing when some direction d is faced by all its triangles and by all those that meet a
    /// convex region R holding the old and the new star, and those all belong to one component
    /// (R: first the box of both stars, taken a grid cell at a time; then that box cut to the
    /// slab of slab_around(), which leaves out most of a thin wall's far side):
    /// - Along a line the winding number of a closed embedded surface changes by one at each
    ///   crossing, up or down as the triangle faces; one component's takes two values only. So a
    ///   segment along d within R (convex) crosses the surface at most once, and the
    ///   surface in R projects one-to-one onto a plane across d, the old star too; its rim L
    ///   projects to a simple loop and the old star onto the inside of it.
    /// - Each triangle of the new fan (from the new vertex to L) turns the same way seen along d,
    ///   so their angles at the new vertex add up to a turn times the winding number of L's
    ///   projection around it: one. The fan projects one-to-one onto the same inside of L.
    /// - Should the fan meet another triangle T at x off L, the segment along d from x to the
    ///   point of the old star over or under x would lie within R and cross the old surface
    ///   twice (T is part of it); at x on L, T met the old star there before, which the mesh
    ///   allowed only at a vertex or edge T shares with it, and so with the fan.
    /// (Two components, say a sphere within another facing the same way, would break the first
    /// point. The rounds begin free of crossings, so the surface is embedded.) The grids' cells
    /// tell first what the triangles in them have in common; failing that, the triangles met.
    bool intersection_free(Plan& p, Scratch& s) const {
        const std::uint32_t a = vertex(next(p.corner)), b = vertex(prev(p.corner));
        Box& around_star = p.star;
        for (const Box& box : s.boxes) grow(around_star, box.lo), grow(around_star, box.hi);
        Box& region = p.region;
        region = around_star;
        grow(region, positions_[a]), grow(region, positions_[b]);
        p.fan = {~0u, summaries_[p.corner / 3].component};
        for (const detail::Triangle3& t : s.corners) p.fan.facing &= facing_directions(t);
        const auto apart = [&](Summary near) {
            near.add(p.fan);
            if (!near.clears()) return false;
            p.apart = near;
            return true;
        };
        Summary in_cells = settled_grid_.summary(region);
        in_cells.add(moved_grid_.summary(region));
        if (apart(in_cells)) return true;
        const Slab slab = slab_around(p, s);
        // (the triangles met: the visit stops as soon as they cannot clear the collapse)
        Summary met;
        const auto may_clear = [&](Summary near) { return near.add(p.fan), near.clears(); };
        const auto add_met = [&](const GridTriangle& t, const Box&) {
            if (!slab.misses(points_of(triangles_[t.triangle]))) met.add(t.summary);
            return may_clear(met);
        };
        if (visit_triangles(region, add_met) && apart(met)) return true;
        prepare_star(s);
        if (!star_is_a_graph(a, s)) {
            for (std::size_t i = 0; i < s.star.size(); ++i) {
                for (std::size_t j = 0; j < i; ++j) {
                    if (detail::triangles_intersect(s.ids[i], s.corners[i], s.ids[j], s.corners[j])) return false;
                }
            }
        }
        const std::uint32_t removed[2] = {p.corner / 3, opposite_[p.corner] / 3};
        return visit_triangles(around_star, [&](const GridTriangle& t, const Box& box) {
            if (t.triangle == removed[0] || t.triangle == removed[1] || std::find(s.star.begin(), s.star.end(), t.triangle) != s.star.end()) {
                return true;  // the old star, replaced
            }
            const Ids& ids = triangles_[t.triangle];
            const FloatTriangle points = points_of(ids);
            if (slab.misses(points)) return true;  // (the new star lies within the slab)
            const detail::PreparedTriangle other(to_double(points));
            return s.box_columns.for_meeting(box, [&](std::size_t i) { return !detail::triangles_intersect(s.ids[i], s.prepared[i], ids, other); });
        });
    }

    /// The slab across the new fan's normal (the sum of its triangles' cross products) that
    /// holds the old and the new star: their points are the new star's corners (the link and the
    /// new position) and the edge's ends. Convex, so the box of both stars cut to it is too.
    Slab slab_around(const Plan& p, const Scratch& s) const {
        Slab slab;
        for (const detail::Triangle3& t : s.corners) {
            const Vec3d c = cross(sub(t[1], t[0]), sub(t[2], t[0]));
            for (int k = 0; k < 3; ++k) slab.axis[k] += c[k];
        }
        slab.origin = to_double(position_[p.corner]);
        for (const detail::Triangle3& t : s.corners) {
            for (const Vec3d& q : t) slab.add(q);
        }
        slab.add(point(vertex(next(p.corner)))), slab.add(point(vertex(prev(p.corner))));
        return slab;
    }

    FloatTriangle points_of(const Ids& t) const { return {positions_[t[0]], positions_[t[1]], positions_[t[2]]}; }

    /// Each vertex's component (triangles joined by shared vertices) and each component's
    /// enclosed volume (six times, the sum of its triangles' determinants).
    void measure_components() {
        detail::UnionFind sets(positions_.size());
        for (const Ids& t : triangles_) sets.unite(t[0], t[1]), sets.unite(t[0], t[2]);
        std::uint32_t count = 0;
        const std::vector<std::uint32_t> component = sets.labels(count);
        volume_.assign(count, 0);
        for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
            const Ids& ids = triangles_[t];
            summaries_[t].component = component[ids[0]];
            volume_[component[ids[0]]] += dot(point(ids[0]), cross(point(ids[1]), point(ids[2])));
        }
    }

    /// Six times the change of the enclosed volume the collapse of @a p makes: its new star (in
    /// @a s) less the triangles round both ends, both taken from the kept end's old position
    /// (they share their boundary, so the difference does not depend on the origin).
    double volume_change(const Plan& p, const Scratch& s) const {
        const Vec3d origin = point(vertex(next(p.corner)));
        const auto determinant = [&](const Vec3d& a, const Vec3d& b, const Vec3d& c) {
            return dot(sub(a, origin), cross(sub(b, origin), sub(c, origin)));
        };
        double change = 0;
        for (std::size_t i = 0; i < s.star.size(); ++i) {
            const Ids& old = triangles_[s.star[i]];
            change += determinant(s.corners[i][0], s.corners[i][1], s.corners[i][2]) -
                      determinant(point(old[0]), point(old[1]), point(old[2]));
        }
        for (const std::uint32_t t : {p.corner / 3, opposite_[p.corner] / 3}) {
            const Ids& old = triangles_[t];
            change -= determinant(point(old[0]), point(old[1]), point(old[2]));
        }
        return change;
    }

    /// The verdict on @a p, and the box of its new star.
    Verdict check(Plan& p, Scratch& s) const {
        if (!linked_new_star(p, s)) return Verdict::topology;
        if (!geometry_holds(s)) return Verdict::geometry;
        if (!intersection_free(p, s)) return Verdict::intersection;
        p.volume_change = volume_change(p, s);
        return Verdict::passed;
    }

    /// The collapse of the edge opposite @a corner, from a (kept) to b, whose triangles are
    /// t0 = (a, b, c) and t1 = (b, a, d): b's corners become a's, and the two edges left of each
    /// removed triangle are joined; the corners at a go to @a dirty. The corners c and d name
    /// are left to name_opposite_corners().
    void apply(std::uint32_t corner, std::vector<std::uint32_t>& dirty) {
        const std::uint32_t o = opposite_[corner];
        const std::uint32_t a = vertex(next(corner)), b = vertex(prev(corner));
        around(b, [&](std::uint32_t c) { triangles_[c / 3][c % 3] = a; });
        const std::uint32_t x0 = opposite_[next(corner)], y0 = opposite_[prev(corner)];  // across b-c and c-a
        const std::uint32_t x1 = opposite_[next(o)], y1 = opposite_[prev(o)];            // across a-d and d-b
        opposite_[x0] = y0, opposite_[y0] = x0;
        opposite_[x1] = y1, opposite_[y1] = x1;
        vertex_corner_[a] = next(y0);  // y0's triangle runs (., a, c)
        vertex_corner_[b] = kNone;
        alive_[corner / 3] = alive_[o / 3] = 0;
        moved_[corner / 3] = moved_[o / 3] = 1;  // (off the settled grid from now on)
        positions_[a] = position_[corner];
        quadrics_[a] = quadrics_[a] + quadrics_[b];
        around(a, [&](std::uint32_t c) { dirty.push_back(c); });
    }

    /// After apply(@a corner): a corner at c and at d off the removed triangles (whose
    /// opposite_ entries still name the corners across their edges).
    void name_opposite_corners(std::uint32_t corner) {
        const std::uint32_t o = opposite_[corner];
        vertex_corner_[vertex(corner)] = next(opposite_[next(corner)]);
        vertex_corner_[vertex(o)] = next(opposite_[next(o)]);
    }

    Mesh compact() const {
        Mesh mesh;
        std::vector<std::uint32_t> index(positions_.size(), kNone);
        for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
            if (!alive_[t]) continue;
            Ids ids = triangles_[t];
            for (std::uint32_t& v : ids) {
                if (index[v] == kNone) index[v] = std::uint32_t(mesh.vertices.size()), mesh.vertices.push_back(positions_[v]);
                v = index[v];
            }
            mesh.triangles.push_back(ids);
        }
        return mesh;
    }

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

}  // namespace

Mesh decimate_mesh(const Mesh& mesh, const DecimateOptions& options, DecimateReport* report) {
    if (!(options.keep_fraction >= 0 && options.keep_fraction <= 1)) {
        throw UsageError("decimate: expected a share of triangles to keep in [0, 1], got " + std::to_string(options.keep_fraction));
    }
    if (!(options.max_error >= 0)) throw UsageError("decimate: expected a maximum error >= 0, got " + std::to_string(options.max_error));
    detail::check_indices(mesh);
    Decimator decimator(mesh, options);
    if (!decimator.closed_manifold()) check_closed_manifold(mesh);  // throws, naming the faults
    DecimateReport local;
    Mesh result = decimator.run(local);
    if (report) *report = local;
    return result;
}

}  // namespace vdbmesh
