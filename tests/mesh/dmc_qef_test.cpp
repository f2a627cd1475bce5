// Tests of Dual Marching Cubes' 4D QEF (src/mesh/dmc_qef.cpp) on fields whose answer is known
// by hand: a plane (rank 1: the vertex stays at the mass point, on the plane's graph), an
// edge and a corner where faces meet (rank 2 and 3: the vertex goes onto the feature), sums
// of children, and a minimiser outside its cell (clamped into it).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include "mesh/dmc_qef.h"

namespace vdbmesh {
namespace {

using detail::Point3d;
using detail::Qef4;

/// A field given with its gradient (exact, as a distance-like field of planes has).
struct Field {
    std::function<double(const Point3d&)> value;
    std::function<Point3d(const Point3d&)> gradient;
};

/// The QEF of the integer samples of @a field in [lo, hi]^3.
Qef4 sampled(const Field& field, int lo, int hi) {
    Qef4 qef;
    for (int x = lo; x <= hi; ++x) {
        for (int y = lo; y <= hi; ++y) {
            for (int z = lo; z <= hi; ++z) {
                const Point3d p = {double(x), double(y), double(z)};
                qef.add_sample(p, field.value(p), field.gradient(p));
            }
        }
    }
    return qef;
}

/// Inside where positive; the distance to the plane x = 3.3 (inside below it).
const Field kPlane = {[](const Point3d& p) { return 3.3 - p[0]; }, [](const Point3d&) { return Point3d{-1, 0, 0}; }};

/// A convex edge along z: inside where x < 3.3 and y < 2.6 (the smaller distance rules).
const Field kEdge = {[](const Point3d& p) { return std::min(3.3 - p[0], 2.6 - p[1]); },
                     [](const Point3d& p) { return 3.3 - p[0] < 2.6 - p[1] ? Point3d{-1, 0, 0} : Point3d{0, -1, 0}; }};

/// A convex corner: inside where x < 3.3, y < 2.6 and z < 2.8.
const Field kCorner = {[](const Point3d& p) { return std::min({3.3 - p[0], 2.6 - p[1], 2.8 - p[2]}); },
                       [](const Point3d& p) {
                           const double a = 3.3 - p[0], b = 2.6 - p[1], c = 2.8 - p[2];
                           if (a <= b && a <= c) return Point3d{-1, 0, 0};
                           return b <= c ? Point3d{0, -1, 0} : Point3d{0, 0, -1};
                       }};

const Point3d kLo = {-0.5, -0.5, -0.5}, kHi = {5.5, 5.5, 5.5};

TEST(DmcQefTest, PlaneFitsExactlyAndKeepsTheMassPoint) {
    const Qef4 qef = sampled(kPlane, 0, 5);
    const Qef4::Solution s = qef.solve(kLo, kHi);
    EXPECT_NEAR(s.error, 0.0, 1e-9);
    // Rank 1: the directions along the plane stay at the mass point (2.5, 2.5, 2.5), and the
    // point (x, w) lies on the graph w = 3.3 - x.
    EXPECT_NEAR(s.position[1], 2.5, 1e-9);
    EXPECT_NEAR(s.position[2], 2.5, 1e-9);
    EXPECT_NEAR(s.value, 3.3 - s.position[0], 1e-9);
}

TEST(DmcQefTest, EdgeIsRankTwoAndTheVertexGoesOntoIt) {
    const Qef4::Solution s = sampled(kEdge, 0, 5).solve(kLo, kHi);
    // The graphs of the two faces meet along a ridge whose point at the isovalue is the edge
    // (3.3, 2.6, z); the vertex is moved along the ridge to the surface (a small margin on
    // the samples' side), z staying at the mass point.
    EXPECT_NEAR(s.position[0], 3.3, 0.05);
    EXPECT_NEAR(s.position[1], 2.6, 0.05);
    EXPECT_NEAR(s.position[2], 2.5, 1e-6);
    EXPECT_LT(std::abs(s.value), 0.05);
}

TEST(DmcQefTest, CornerIsRankThreeAndTheVertexGoesOntoIt) {
    const Qef4::Solution s = sampled(kCorner, 0, 5).solve(kLo, kHi);
    EXPECT_NEAR(s.position[0], 3.3, 0.05);
    EXPECT_NEAR(s.position[1], 2.6, 0.05);
    EXPECT_NEAR(s.position[2], 2.8, 0.05);
    EXPECT_LT(std::abs(s.value), 0.05);
}

TEST(DmcQefTest, ChildrenAddUpToTheParent) {
    // A parent's QEF is the sum of its children's: the same as adding every sample to one.
    Qef4 sum = sampled(kCorner, 0, 2);
    sum.add(sampled(kCorner, 3, 5));
    Qef4 direct;
    for (int lo : {0, 3}) {
        for (int x = lo; x <= lo + 2; ++x) {
            for (int y = lo; y <= lo + 2; ++y) {
                for (int z = lo; z <= lo + 2; ++z) {
                    const Point3d p = {double(x), double(y), double(z)};
                    direct.add_sample(p, kCorner.value(p), kCorner.gradient(p));
                }
            }
        }
    }
    EXPECT_EQ(sum.count(), direct.count());
    const Qef4::Solution a = sum.solve(kLo, kHi), b = direct.solve(kLo, kHi);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.position[std::size_t(k)], b.position[std::size_t(k)], 1e-9);
    EXPECT_NEAR(a.value, b.value, 1e-9);
    EXPECT_NEAR(a.error, b.error, 1e-9);
}

TEST(DmcQefTest, MinimiserOutsideTheCellIsClamped) {
    // The corner lies at (3.3, 2.6, 2.8); a cell [0, 2]^3 cannot hold it.
    const Point3d lo = {-0.5, -0.5, -0.5}, hi = {2.0, 2.0, 2.0};
    const Qef4 qef = sampled(kCorner, 0, 5);
    const Qef4::Solution s = qef.solve(lo, hi);
    for (int k = 0; k < 3; ++k) {
        EXPECT_GE(s.position[std::size_t(k)], lo[std::size_t(k)]);
        EXPECT_LE(s.position[std::size_t(k)], hi[std::size_t(k)]);
    }
    EXPECT_GT(s.error, 0.0);  // the corner's planes cannot all pass through a point of the cell
}

}  // namespace
}  // namespace vdbmesh
