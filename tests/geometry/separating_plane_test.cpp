// The quick proofs that triangles do not cross (include/vdbmesh/separating_plane.h), judged by the
// exact test they stand in for (detail::triangles_intersect): a proof must never be given for a
// pair that test finds crossing, on random pairs made to be close calls (nearly coplanar,
// touching, sharing a corner or an edge). And triangles_intersect() on prepared triangles, which
// tries the proof for the case first: the same answer as the exact test alone, whichever corners
// the triangles share and wherever those sit in each triangle (the dispatch hands each proof the
// corners and apexes it names).
#include <gtest/gtest.h>

#include <optional>
#include <random>
#include <vector>

#include "vdbmesh/separating_plane.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh {
namespace {

using detail::Point3;
using detail::Triangle3;
using Ids = std::array<std::uint32_t, 3>;

/// A point of float coordinates (as mesh vertices are) in [-1, 1]^2 x [-flat, flat].
Point3 random_point(std::mt19937& random, double flat) {
    std::uniform_real_distribution<float> plane(-1, 1), height(float(-flat), float(flat));
    return {plane(random), plane(random), height(random)};
}

/// A random pair of triangles made to be a close call (pair @a n: a third of them nearly
/// coplanar, a third exactly) sharing @a shared corners: none, t[0] as u[0], or also t[2] as u[1]
/// (t's edge t[2] -> t[0], the other way in u); none when one is degenerate.
struct Pair {
    Triangle3 t, u;
    Ids t_ids{0, 1, 2}, u_ids{3, 4, 5};
};
std::optional<Pair> random_pair(std::mt19937& random, int n, int shared) {
    const double flat = n % 3 == 0 ? 1.0 : n % 3 == 1 ? 1e-3 : 0.0;
    Pair pair;
    for (Triangle3* triangle : {&pair.t, &pair.u}) {
        for (Point3& p : *triangle) p = random_point(random, flat);
    }
    if (shared >= 1) pair.u[0] = pair.t[0], pair.u_ids[0] = 0;
    if (shared == 2) pair.u[1] = pair.t[2], pair.u_ids[1] = 2;
    const auto degenerate = [](const Triangle3& t) { return detail::collinear(t[0], t[1], t[2]); };
    if (degenerate(pair.t) || degenerate(pair.u)) return std::nullopt;
    return pair;
}

/// Whether the quick proof for the case settles a pair of random_pair(), handed its corners by hand.
bool settled_by_hand(int shared, const Pair& pair) {
    const Triangle3 &t = pair.t, &u = pair.u;
    const detail::PreparedTriangle prepared_t(t), prepared_u(u);
    if (shared == 0) return detail::certainly_apart(prepared_t, prepared_u) || detail::certainly_apart_by_plane(prepared_t, prepared_u);
    if (shared == 1) return detail::certainly_apart_of_plane(prepared_t, 0, prepared_u, 0) || detail::certainly_meet_only_at(t, 0, u[1], u[2]);
    return detail::certainly_meet_only_on_edge(t[2], t[0], t[1], u[2]);
}

struct Counts {
    int proven = 0, crossing = 0;
};

/// Random pairs sharing @a shared corners (0, 1 or 2); returns how many the quick proofs settled
/// and how many cross.
Counts check_pairs(int shared, int pairs) {
    std::mt19937 random(1234 + shared);
    Counts counts;
    for (int n = 0; n < pairs; ++n) {
        const std::optional<Pair> pair = random_pair(random, n, shared);
        if (!pair) continue;
        const bool proven = settled_by_hand(shared, *pair);
        const bool crossing = detail::triangles_intersect(pair->t_ids, pair->t, pair->u_ids, pair->u);
        EXPECT_FALSE(proven && crossing) << "pair " << n << " (" << shared << " shared) proven apart but crossing";
        counts.proven += proven;
        counts.crossing += crossing;
    }
    return counts;
}

TEST(SeparatingPlaneTest, NoProofForACrossingPair) {
    for (int shared = 0; shared <= 2; ++shared) {
        const Counts counts = check_pairs(shared, 30000);
        // Both kinds occur, so the assertion above is exercised on each side.
        EXPECT_GT(counts.proven, 3000) << shared << " shared";
        EXPECT_GT(counts.crossing, 300) << shared << " shared";
    }
}

TEST(SeparatingPlaneTest, TouchingIsNotApart) {
    // Touching counts as meeting (CGAL's convention): a corner of u on t's edge, and the same
    // point under two ids.
    const Triangle3 t{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
    using Prepared = detail::PreparedTriangle;
    const Prepared prepared_t(t);
    const Prepared on_edge(Triangle3{{{0.5, 0, 0}, {0.5, -1, 0.5}, {0.5, -1, -0.5}}});
    const Prepared at_corner(Triangle3{{{1, 0, 0}, {2, 0, 1}, {2, 1, 0}}});
    EXPECT_FALSE(detail::certainly_apart(prepared_t, on_edge));
    EXPECT_FALSE(detail::certainly_apart(prepared_t, at_corner));
    EXPECT_TRUE(detail::certainly_apart(prepared_t, Prepared(Triangle3{{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}})));
    EXPECT_FALSE(detail::certainly_apart_by_plane(prepared_t, on_edge));
    EXPECT_TRUE(detail::certainly_apart_by_plane(prepared_t, Prepared(Triangle3{{{5, 5, 1}, {-5, 5, 2}, {0, -5, 1}}})));
    // Coplanar neighbours across an edge are proven apart, folded onto each other are not.
    EXPECT_TRUE(detail::certainly_meet_only_on_edge(t[1], t[2], t[0], {1, 1, 0}));
    EXPECT_FALSE(detail::certainly_meet_only_on_edge(t[1], t[2], t[0], {0.2, 0.2, 0}));
    // Two wedges at a shared corner, apart in the plane; overlapping ones are not.
    EXPECT_TRUE(detail::certainly_meet_only_at(t, 0, {-1, -0.1, 0}, {-0.1, -1, 0}));
    EXPECT_FALSE(detail::certainly_meet_only_at(t, 0, {1, 1, 0}, {0.5, 2, 0}));
}

/// A triangle's corners (or ids) turned so that corner 0 sits at @a first.
template <class T>
std::array<T, 3> turned(const std::array<T, 3>& corners, int first) {
    std::array<T, 3> result;
    for (int k = 0; k < 3; ++k) result[std::size_t((first + k) % 3)] = corners[std::size_t(k)];
    return result;
}

/// Random pairs of random_pair() sharing @a shared corners, each put with both triangles' corners
/// turned every way: the answer must not change, and the proof must settle what it settles when
/// handed the corners by hand (but for rounding on a few close calls where the corners come in
/// another order), which it would not were it handed the wrong corners.
void expect_the_same_every_way(int shared, int pairs) {
    std::mt19937 random(std::uint32_t(1234 + shared));
    const int turns = shared == 0 ? 1 : 3;
    std::vector<int> settled(9, 0);
    int crossing = 0, apart = 0, by_hand = 0;
    for (int n = 0; n < pairs; ++n) {
        const std::optional<Pair> pair = random_pair(random, n, shared);
        if (!pair) continue;
        const bool exact = detail::triangles_intersect(pair->t_ids, pair->t, pair->u_ids, pair->u);
        ++(exact ? crossing : apart);
        const bool settled_as_put = settled_by_hand(shared, *pair);
        by_hand += settled_as_put;
        for (int i = 0; i < turns; ++i) {
            for (int j = 0; j < turns; ++j) {
                const Ids ti = turned(pair->t_ids, i), uj = turned(pair->u_ids, j);
                const detail::PreparedTriangle tp(turned(pair->t, i)), up(turned(pair->u, j));
                EXPECT_EQ(detail::triangles_intersect(ti, tp, uj, up), exact) << "pair " << n << " turned " << i << ", " << j;
                const bool proven = detail::proven_apart(ti, tp, uj, up);
                EXPECT_FALSE(proven && exact) << "pair " << n << " turned " << i << ", " << j << ": proven apart but crossing";
                if (i == 0 && j == 0) EXPECT_EQ(proven, settled_as_put) << "pair " << n;
                settled[std::size_t(3 * i + j)] += proven;
            }
        }
    }
    // Both answers occur often (so a proof settling a crossing pair would be caught), and the
    // proofs settle many pairs, as many as by hand however the corners are turned (rounding
    // differs with the order of the corners: a few in a thousand at most).
    EXPECT_GT(crossing, pairs / 20) << shared << " shared";
    EXPECT_GT(apart, pairs / 20) << shared << " shared";
    EXPECT_GT(by_hand, pairs / 10) << shared << " shared";
    for (int k = 0; k < turns * turns; ++k) {
        const int i = k / turns, j = k % turns;
        EXPECT_NEAR(settled[std::size_t(3 * i + j)], by_hand, pairs / 200) << shared << " shared, turned " << i << ", " << j;
    }
}

TEST(TriangleIntersectTest, PreparedAgreesWithExactHoweverTheCornersAreTurned) {
    for (int shared = 0; shared <= 2; ++shared) expect_the_same_every_way(shared, 6000);
}

TEST(TriangleIntersectTest, PreparedFindsFoldsAtEachSharedCorner) {
    // u folded back onto t through the shared corner (or edge), wherever that sits: crossing.
    const Triangle3 t{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
    const Ids t_ids{0, 1, 2};
    for (int i = 0; i < 3; ++i) {
        // u shares t[i] and reaches over t's middle, in t's plane: they overlap beyond the corner.
        const Point3 middle{1.0 / 3, 1.0 / 3, 0};
        const Point3 far{2 * middle[0] - t[i][0] + 0.1, 2 * middle[1] - t[i][1] + 0.05, 0};
        const Triangle3 u{t[i], far, {far[0] - 0.05, far[1] + 0.1, 0}};
        const Ids u_ids{t_ids[i], 7, 8};
        EXPECT_TRUE(detail::triangles_intersect(t_ids, detail::PreparedTriangle(t), u_ids, detail::PreparedTriangle(u))) << i;
        // u across t's edge t[i] -> t[i + 1] folded onto t (its apex at t's middle): overlapping.
        const Triangle3 folded{t[(i + 1) % 3], t[i], middle};
        const Ids folded_ids{t_ids[(i + 1) % 3], t_ids[i], 9};
        EXPECT_TRUE(detail::triangles_intersect(t_ids, detail::PreparedTriangle(t), folded_ids, detail::PreparedTriangle(folded))) << i;
        // ... and unfolded (the apex mirrored across the edge): meeting only on it.
        const Point3& a = t[i];
        const Point3& b = t[(i + 1) % 3];
        const Point3 mirrored{a[0] + b[0] - middle[0], a[1] + b[1] - middle[1], 0};
        const Triangle3 unfolded{b, a, mirrored};
        EXPECT_FALSE(detail::triangles_intersect(t_ids, detail::PreparedTriangle(t), folded_ids, detail::PreparedTriangle(unfolded))) << i;
    }
}

}  // namespace
}  // namespace vdbmesh
