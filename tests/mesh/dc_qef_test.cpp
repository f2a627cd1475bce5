// The QEF of intersection-free contouring (src/mesh/dc_qef.h): its minimiser where the planes
// pin a point down, and, where they do not (flat and ridge cells: a rank-deficient A^T A), the
// point nearest the planes' points' mean, so such a cell's vertex stays on its surface's middle.

#include <gtest/gtest.h>

#include <cmath>

#include "mesh/dc_qef.h"

namespace vdbmesh::detail {
namespace {

void expect_near(const Point3d& got, const Point3d& want) {
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(got[a], want[a], 1e-9) << "axis " << a;
}

TEST(IfcQefTest, ThreePlanesMeetAtTheirCorner) {
    Qef3 qef;
    qef.add_plane({1, 0, 0}, {1, 0, 0});
    qef.add_plane({5, 2, 0}, {0, 1, 0});
    qef.add_plane({0, 7, 3}, {0, 0, 1});
    expect_near(qef.minimiser(), {1, 2, 3});
    EXPECT_NEAR(qef.residual({1, 2, 3}), 0, 1e-12);
}

TEST(IfcQefTest, FlatCellKeepsItsVertexAtThePointsMean) {
    Qef3 qef;
    for (const Point3d& p : {Point3d{0, 0, 5}, Point3d{2, 0, 5}, Point3d{0, 4, 5}, Point3d{2, 4, 5}}) qef.add_plane(p, {0, 0, 1});
    expect_near(qef.minimiser(), {1, 2, 5});
}

TEST(IfcQefTest, RidgeKeepsItsVertexOnTheCreaseAtThePointsMean) {
    // Two planes meeting along the line x = 3, z = 1 (along y), sampled at y = 0 and y = 4.
    const double s = 1 / std::sqrt(2.0);
    Qef3 qef;
    for (double y : {0.0, 4.0}) {
        qef.add_plane({4, y, 0}, {s, 0, s});
        qef.add_plane({2, y, 0}, {-s, 0, s});
    }
    expect_near(qef.minimiser(), {3, 2, 1});
}

TEST(IfcQefTest, ChildrenSumToTheParent) {
    Qef3 a, b, whole;
    a.add_plane({1, 0, 0}, {1, 0, 0});
    b.add_plane({5, 2, 0}, {0, 1, 0});
    b.add_plane({0, 7, 3}, {0, 0, 1});
    for (const auto& [p, n] : {std::pair<Point3d, Point3d>{{1, 0, 0}, {1, 0, 0}}, {{5, 2, 0}, {0, 1, 0}}, {{0, 7, 3}, {0, 0, 1}}}) {
        whole.add_plane(p, n);
    }
    a.add(b);
    EXPECT_EQ(a.count(), whole.count());
    expect_near(a.minimiser(), whole.minimiser());
    EXPECT_NEAR(a.residual({0, 0, 0}), whole.residual({0, 0, 0}), 1e-12);
}

}  // namespace
}  // namespace vdbmesh::detail
