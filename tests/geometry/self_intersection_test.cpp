// find_self_intersections() and the exact predicates under it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/exact_predicates.h"
#include "test_meshes.h"
#include "vdbmesh/analysis.h"

namespace vdbmesh {
namespace {

using Tri = std::array<std::array<float, 3>, 3>;

std::size_t pairs_of(const std::vector<Tri>& triangles) { return find_self_intersections(test::triangle_soup(triangles)).size(); }

TEST(ExactPredicatesTest, Orient2dIsExactNearALine) {
    // Points 0.5 + i ulp, 0.5 + j ulp against the line through (12, 12) and (24, 24): the exact
    // sign is that of j - i, which a plain double evaluation gets wrong (Shewchuk's example).
    const double ulp = std::ldexp(1.0, -53);
    for (int i = 0; i < 32; ++i) {
        for (int j = 0; j < 32; ++j) {
            const int sign = detail::orient2d({12, 12}, {24, 24}, {0.5 + i * ulp, 0.5 + j * ulp});
            ASSERT_EQ(sign, (j > i) - (j < i)) << i << " " << j;
        }
    }
}

TEST(ExactPredicatesTest, Orient3dIsExactOnALargePlane) {
    // Points on the plane z = x + y with x near 2^40: every coordinate is exact, the products
    // are not, so only the exact stage can say "coplanar".
    const double big = std::ldexp(1.0, 40);
    const auto on_plane = [&](double x, double y) { return detail::Point3{x, y, x + y}; };
    const detail::Point3 a = on_plane(big + 1, 0.125), b = on_plane(big + 7, 0.375), c = on_plane(big + 3, 0.875);
    const detail::Point3 d = on_plane(big + 5, 0.0625);
    EXPECT_EQ(detail::orient3d(a, b, c, d), 0);
    const int above = detail::orient3d(a, b, c, {d[0], d[1], d[2] + 1000});
    ASSERT_NE(above, 0);
    EXPECT_EQ(detail::orient3d(a, b, c, {d[0], d[1], std::nextafter(d[2], 1e300)}), above);
    EXPECT_EQ(detail::orient3d(a, b, c, {d[0], d[1], std::nextafter(d[2], -1e300)}), -above);
}

TEST(ExactPredicatesTest, CollinearIsExact) {
    EXPECT_TRUE(detail::collinear({0, 0, 0}, {1, 2, 3}, {3, 6, 9}));
    EXPECT_FALSE(detail::collinear({0, 0, 0}, {1, 2, 3}, {3, 6, std::nextafter(9.0, 10.0)}));
}

TEST(SelfIntersectionTest, CleanMeshesHaveNone) {
    EXPECT_TRUE(find_self_intersections(test::torus(64, 32)).empty());
    EXPECT_TRUE(find_self_intersections(test::cube()).empty());
}

TEST(SelfIntersectionTest, DisjointCrossingAndTouching) {
    const Tri base{{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}};
    EXPECT_EQ(pairs_of({base, {{{0, 0, 1}, {2, 0, 1}, {0, 2, 1}}}}), 0u);                   // parallel
    EXPECT_EQ(pairs_of({base, {{{0.5f, 0.5f, -1}, {0.5f, 0.5f, 1}, {3, 3, 0}}}}), 1u);     // crossing
    // A corner on the other's interior, without a shared index: touching counts (as in CGAL).
    EXPECT_EQ(pairs_of({base, {{{0.5f, 0.5f, 0}, {0.5f, 0.5f, 1}, {1, 3, 1}}}}), 1u);
    // Coplanar and overlapping, no shared corner.
    EXPECT_EQ(pairs_of({base, {{{0.5f, 0.5f, 0}, {3, 0.5f, 0}, {0.5f, 3, 0}}}}), 1u);
    // Coplanar, one inside the other.
    EXPECT_EQ(pairs_of({base, {{{0.25f, 0.25f, 0}, {0.5f, 0.25f, 0}, {0.25f, 0.5f, 0}}}}), 1u);
    // Coplanar and apart.
    EXPECT_EQ(pairs_of({base, {{{3, 3, 0}, {4, 3, 0}, {3, 4, 0}}}}), 0u);
}

TEST(SelfIntersectionTest, SharedEdge) {
    const Tri base{{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}};
    EXPECT_EQ(pairs_of({base, {{{2, 0, 0}, {0, 0, 0}, {1, -1, 0}}}}), 0u);  // coplanar, opposite sides
    EXPECT_EQ(pairs_of({base, {{{2, 0, 0}, {0, 0, 0}, {1, 0, 1}}}}), 0u);   // folded at 90 degrees
    EXPECT_EQ(pairs_of({base, {{{2, 0, 0}, {0, 0, 0}, {1, 1, 0}}}}), 1u);   // folded flat onto it
    EXPECT_EQ(pairs_of({base, {{{0, 0, 0}, {2, 0, 0}, {1, 0.1f, 0}}}}), 1u);  // same side, same winding
}

TEST(SelfIntersectionTest, SharedCorner) {
    const Tri base{{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}};
    EXPECT_EQ(pairs_of({base, {{{0, 0, 0}, {-1, 0, 0}, {0, -1, 0}}}}), 0u);  // coplanar, apart
    EXPECT_EQ(pairs_of({base, {{{0, 0, 0}, {0, 0, 1}, {1, -1, 1}}}}), 0u);   // another plane, apart
    EXPECT_EQ(pairs_of({base, {{{0, 0, 0}, {1, 1, 0}, {-1, 1, 0}}}}), 1u);   // coplanar, overlapping
    EXPECT_EQ(pairs_of({base, {{{0, 0, 0}, {1, 1, -1}, {1, 1, 1}}}}), 1u);   // piercing through it
    // Touching along a line through the shared corner, in another plane: a fold onto an edge.
    EXPECT_EQ(pairs_of({base, {{{0, 0, 0}, {1, 0, 0}, {1, 0, 1}}}}), 1u);
}

TEST(SelfIntersectionTest, SharingIsByPositionNotIndex) {
    // The same two triangles as a welded mesh and as a soup: a shared edge either way.
    const Mesh welded{{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {2, 2, 0}}, {{0, 1, 2}, {1, 3, 2}}};
    EXPECT_TRUE(find_self_intersections(welded).empty());
    EXPECT_EQ(pairs_of({{{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}}, {{{2, 0, 0}, {2, 2, 0}, {0, 2, 0}}}}), 0u);
}

TEST(SelfIntersectionTest, DegenerateTrianglesAreSkipped) {
    const Tri base{{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}};
    EXPECT_EQ(pairs_of({base, {{{0.5f, 0.5f, -1}, {0.5f, 0.5f, 0}, {0.5f, 0.5f, 1}}}}), 0u);
}

TEST(SelfIntersectionTest, HierarchyFindsWhatBruteForceFinds) {
    std::mt19937 random(7);
    std::uniform_real_distribution<float> coordinate(0, 10), offset(-1.5f, 1.5f);
    std::vector<Tri> soup;
    for (int i = 0; i < 200; ++i) {
        Tri t;
        const std::array<float, 3> centre{coordinate(random), coordinate(random), coordinate(random)};
        for (auto& p : t) {
            for (int k = 0; k < 3; ++k) p[k] = centre[k] + offset(random);
        }
        soup.push_back(t);
    }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> expected;
    for (std::uint32_t i = 0; i < soup.size(); ++i) {
        for (std::uint32_t j = i + 1; j < soup.size(); ++j) {
            if (pairs_of({soup[i], soup[j]}) == 1) expected.emplace_back(i, j);
        }
    }
    EXPECT_GT(expected.size(), 10u);
    EXPECT_EQ(find_self_intersections(test::triangle_soup(soup)), expected);
}

}  // namespace
}  // namespace vdbmesh
