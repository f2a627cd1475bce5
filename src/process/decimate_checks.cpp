// The checks of one collapse (process/decimator.h), against the mesh at the start of its round:
// the link condition, degenerate and turned triangles, the change of the enclosed volume, and
// crossings (most cleared by intersection_free()'s proof, the others by the exact tests).
#include <algorithm>
#include <cmath>
#include <vector>

#include "process/decimator.h"

namespace vdbmesh::detail::decimation {

constexpr double kMaxTurnDegrees = 75;  ///< largest change of a triangle's normal in one collapse
const double kMinTurnCosine = std::cos(kMaxTurnDegrees * 3.14159265358979323846 / 180);

/// The verdict on @a p, and the box of its new star.
Verdict Decimator::check(Plan& p, Scratch& s) const {
    if (!linked_new_star(p, s)) return Verdict::topology;
    if (!geometry_holds(s)) return Verdict::geometry;
    if (!intersection_free(p, s)) return Verdict::intersection;
    p.volume_change = volume_change(p, s);
    return Verdict::passed;
}

/// Whether the edge of @a p meets the link condition (its ends' neighbours in common are only
/// the two opposite corners; the kept vertex keeps three neighbours at least), and its new
/// star in @a s (for_new_star(): its triangles, their corners as doubles, their boxes).
bool Decimator::linked_new_star(const Plan& p, Scratch& s) const {
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

bool Decimator::geometry_holds(const Scratch& s) const {
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
bool Decimator::star_is_a_graph(std::uint32_t a, Scratch& s) const {
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
void Decimator::prepare_star(Scratch& s) {
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
bool Decimator::intersection_free(Plan& p, Scratch& s) const {
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
Slab Decimator::slab_around(const Plan& p, const Scratch& s) const {
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

/// Six times the change of the enclosed volume the collapse of @a p makes: its new star (in
/// @a s) less the triangles round both ends, both taken from the kept end's old position
/// (they share their boundary, so the difference does not depend on the origin).
double Decimator::volume_change(const Plan& p, const Scratch& s) const {
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

}  // namespace vdbmesh::detail::decimation
