// The quick proofs that triangles do not cross (src/geometry/separating_plane.h),
// judged by the exact test they stand in for (detail::triangles_intersect): a proof must never
// be given for a pair that test finds crossing, on random pairs made to be close calls (nearly
// coplanar, touching, sharing a corner or an edge).
#include <gtest/gtest.h>

#include <random>

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

struct Counts {
    int proven = 0, crossing = 0;
};

/// Random pairs sharing @a shared corners (0, 1 or 2), a third of them nearly coplanar and a
/// third exactly coplanar; returns how many the quick proofs settled and how many cross.
Counts check_pairs(int shared, int pairs) {
    std::mt19937 random(1234 + shared);
    Counts counts;
    for (int n = 0; n < pairs; ++n) {
        const double flat = n % 3 == 0 ? 1.0 : n % 3 == 1 ? 1e-3 : 0.0;
        const Triangle3 t{random_point(random, flat), random_point(random, flat), random_point(random, flat)};
        Triangle3 u{random_point(random, flat), random_point(random, flat), random_point(random, flat)};
        const Ids t_ids{0, 1, 2};
        Ids u_ids{3, 4, 5};
        if (shared >= 1) u[0] = t[0], u_ids[0] = 0;
        if (shared == 2) u[1] = t[2], u_ids[1] = 2;  // the edge t[2] -> t[0] of t, the other way in u
        if (detail::collinear(t[0], t[1], t[2]) || detail::collinear(u[0], u[1], u[2])) continue;
        bool proven = false;
        const detail::PreparedTriangle prepared_t(t), prepared_u(u);
        if (shared == 0) proven = detail::certainly_apart(prepared_t, prepared_u) || detail::certainly_apart_by_plane(prepared_t, prepared_u);
        if (shared == 1) proven = detail::certainly_apart_of_plane(prepared_t, 0, prepared_u, 0) || detail::certainly_meet_only_at(t, 0, u[1], u[2]);
        if (shared == 2) proven = detail::certainly_meet_only_on_edge(t[2], t[0], t[1], u[2]);
        const bool crossing = detail::triangles_intersect(t_ids, t, u_ids, u);
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

}  // namespace
}  // namespace vdbmesh
