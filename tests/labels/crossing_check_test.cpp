// The label mesher's incremental crossing check (src/labels/crossing_check.h) against every
// pair tested one by one: a first check of all triangles, then rounds that move a few.

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "labels/crossing_check.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh::labels_detail {
namespace {

detail::Triangle3 corners(const Mesh& mesh, std::uint32_t t) {
    detail::Triangle3 c;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) c[i][k] = mesh.vertices[mesh.triangles[t][i]][k];
    return c;
}

/// What the check must flag: the degenerate triangles among @a asked, and both triangles of
/// every pair with one in @a asked that meets beyond its shared corners, by brute force.
std::vector<std::uint8_t> expected(const Mesh& mesh, const std::set<std::uint32_t>& asked) {
    const std::size_t n = mesh.triangles.size();
    std::vector<std::uint8_t> flagged(n, 0), degenerate(n, 0);
    for (std::uint32_t t = 0; t < n; ++t) {
        const detail::Triangle3 c = corners(mesh, t);
        degenerate[t] = detail::collinear(c[0], c[1], c[2]);
        if (degenerate[t] && asked.count(t)) flagged[t] = 1;
    }
    for (std::uint32_t t = 0; t < n; ++t)
        for (std::uint32_t u = t + 1; u < n; ++u)
            if ((asked.count(t) || asked.count(u)) && !degenerate[t] && !degenerate[u] &&
                detail::triangles_intersect(mesh.triangles[t], corners(mesh, t), mesh.triangles[u], corners(mesh, u)))
                flagged[t] = flagged[u] = 1;
    return flagged;
}

/// Small triangles scattered in a box, some sharing a corner with the one before.
Mesh scattered_triangles(std::mt19937& random, int count) {
    std::uniform_real_distribution<float> place(0, 8), offset(-1, 1);
    Mesh mesh;
    for (int t = 0; t < count; ++t) {
        const std::array<float, 3> centre{place(random), place(random), place(random)};
        std::array<std::uint32_t, 3> tri;
        for (int i = 0; i < 3; ++i) {
            tri[i] = std::uint32_t(mesh.vertices.size());
            mesh.vertices.push_back({centre[0] + offset(random), centre[1] + offset(random), centre[2] + offset(random)});
        }
        if (t > 0 && t % 3 == 0) tri[0] = mesh.triangles.back()[1];  // a shared corner
        mesh.triangles.push_back(tri);
    }
    return mesh;
}

TEST(CrossingCheckTest, EachRoundFlagsWhatTestingEveryPairFinds) {
    std::mt19937 random(7);
    Mesh mesh = scattered_triangles(random, 160);
    const std::size_t n = mesh.triangles.size();
    CrossingCheck check(1.0);
    std::set<std::uint32_t> all;
    for (std::uint32_t t = 0; t < n; ++t) all.insert(t);
    const std::vector<std::uint8_t> first = check.crossing_triangles(mesh, {});
    EXPECT_EQ(first, expected(mesh, all));
    ASSERT_GT(std::count(first.begin(), first.end(), 1), 10);  // the scatter has crossings to find
    // Rounds: a few vertices move (some far, out of the first check's bounds); the check is
    // told the triangles round them and must flag what brute force flags for those.
    std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(mesh.vertices.size() - 1));
    std::uniform_real_distribution<float> step(-1.5f, 1.5f);
    for (int round = 0; round < 12; ++round) {
        std::set<std::uint32_t> moved_vertices;
        for (int i = 0; i < 8; ++i) moved_vertices.insert(pick(random));
        for (std::uint32_t v : moved_vertices)
            for (int k = 0; k < 3; ++k) mesh.vertices[v][k] += round == 5 ? 9 * step(random) : step(random);
        std::set<std::uint32_t> moved;
        for (std::uint32_t t = 0; t < n; ++t)
            for (std::uint32_t v : mesh.triangles[t])
                if (moved_vertices.count(v)) moved.insert(t);
        const std::vector<std::uint8_t> found = check.crossing_triangles(mesh, std::vector<std::uint32_t>(moved.begin(), moved.end()));
        EXPECT_EQ(found, expected(mesh, moved)) << "round " << round;
    }
}

TEST(CrossingCheckTest, FlagsAMovedTriangleCrossingOneMovedBefore) {
    // Two triangles far apart; the first moves (still apart), then the second moves onto it:
    // the pair is found through the index of moved triangles, not the first check's grid.
    Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}, {6, 5, 5}, {5, 6, 5}};
    mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
    CrossingCheck check(0.5);
    EXPECT_EQ(check.crossing_triangles(mesh, {}), (std::vector<std::uint8_t>{0, 0}));
    for (int i = 0; i < 3; ++i) mesh.vertices[std::size_t(i)][2] += 3;
    EXPECT_EQ(check.crossing_triangles(mesh, {0}), (std::vector<std::uint8_t>{0, 0}));
    mesh.vertices[3] = {0.2f, 0.2f, 2.5f};
    mesh.vertices[4] = {0.2f, 0.2f, 3.5f};
    mesh.vertices[5] = {0.3f, 0.3f, 3.5f};
    EXPECT_EQ(check.crossing_triangles(mesh, {1}), (std::vector<std::uint8_t>{1, 1}));
}

TEST(CrossingCheckTest, FlagsADegenerateMovedTriangle) {
    Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {{0, 1, 2}};
    CrossingCheck check(1.0);
    EXPECT_EQ(check.crossing_triangles(mesh, {}), (std::vector<std::uint8_t>{0}));
    mesh.vertices[2] = {2, 0, 0};  // collinear
    EXPECT_EQ(check.crossing_triangles(mesh, {0}), (std::vector<std::uint8_t>{1}));
}

}  // namespace
}  // namespace vdbmesh::labels_detail
