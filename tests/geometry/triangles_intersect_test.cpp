// triangles_intersect() on prepared triangles (src/geometry/separating_plane.h), which tries a
// quick proof before the exact test: the same answer as the exact test alone, whichever corners
// the triangles share and wherever those sit in each triangle (the dispatch hands each proof the
// corners and apexes it names), on random pairs made to be close calls.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "geometry/separating_plane.h"
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

/// A triangle's corners (or ids) turned so that corner 0 sits at @a first.
template <class T>
std::array<T, 3> turned(const std::array<T, 3>& corners, int first) {
    std::array<T, 3> result;
    for (int k = 0; k < 3; ++k) result[std::size_t((first + k) % 3)] = corners[std::size_t(k)];
    return result;
}

/// Whether the proof of separating_plane.h for the case settles a pair put as in
/// expect_the_same_every_way(), handed its corners by hand.
bool settled_by_hand(int shared, const Triangle3& t, const Triangle3& u) {
    const detail::PreparedTriangle tp(t), up(u);
    if (shared == 0) return detail::certainly_apart(tp, up) || detail::certainly_apart_by_plane(tp, up);
    if (shared == 1) return detail::certainly_apart_of_plane(tp, 0, up, 0) || detail::certainly_meet_only_at(t, 0, u[1], u[2]);
    return detail::certainly_meet_only_on_edge(t[0], t[1], t[2], u[2]);
}

/// Random pairs (a third of them nearly coplanar, a third exactly) sharing nothing (@a shared 0),
/// t's corner 0 as u's corner 0 (1), or t's edge 0 -> 1 as u's edge 1 -> 0 (2), each put with
/// its corners turned every way: the answer must not change, and the proof must settle what it
/// settles when handed the corners by hand (but for rounding on a few close calls where the
/// corners come in another order), which it would not were it handed the wrong corners.
void expect_the_same_every_way(int shared, int pairs) {
    std::mt19937 random(std::uint32_t(1234 + shared));
    const int turns = shared == 0 ? 1 : 3;
    std::vector<int> settled(9, 0);
    int crossing = 0, apart = 0, by_hand = 0;
    for (int n = 0; n < pairs; ++n) {
        const double flat = n % 3 == 0 ? 1.0 : n % 3 == 1 ? 1e-3 : 0.0;
        const Triangle3 t{random_point(random, flat), random_point(random, flat), random_point(random, flat)};
        Triangle3 u{random_point(random, flat), random_point(random, flat), random_point(random, flat)};
        const Ids t_ids{10, 11, 12};
        Ids u_ids{20, 21, 22};
        if (shared >= 1) u[0] = t[shared == 1 ? 0 : 1], u_ids[0] = t_ids[shared == 1 ? 0 : 1];
        if (shared == 2) u[1] = t[0], u_ids[1] = t_ids[0];
        if (detail::collinear(t[0], t[1], t[2]) || detail::collinear(u[0], u[1], u[2])) continue;
        const bool exact = detail::triangles_intersect(t_ids, t, u_ids, u);
        ++(exact ? crossing : apart);
        const bool settled_as_put = settled_by_hand(shared, t, u);
        by_hand += settled_as_put;
        for (int i = 0; i < turns; ++i) {
            for (int j = 0; j < turns; ++j) {
                const Ids ti = turned(t_ids, i), uj = turned(u_ids, j);
                const detail::PreparedTriangle tp(turned(t, i)), up(turned(u, j));
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
