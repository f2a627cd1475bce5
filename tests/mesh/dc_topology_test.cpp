// The 27-sign topology test of dc merges (src/mesh/dc_topology.cpp), judged against the
// Marching Cubes surface of the 2 x 2 x 2 unit cells itself: built from the case table,
// welded by grid edge, and measured by components, Euler characteristic, sign changes along
// the cell's edges and the chains on its faces. The test must agree with it on every sign
// pattern whose unit cells qualify as leaf children (one component, no ambiguous face).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include "mesh/dc_topology.h"
#include "vdbmesh/mc_case.h"

namespace vdbmesh::detail {
namespace {

using Signs = std::array<bool, 27>;

bool sign(const Signs& s, int x, int y, int z) { return s[std::size_t(x * 9 + y * 3 + z)]; }

unsigned unit_config(const Signs& s, int x, int y, int z) {
    unsigned config = 0;
    for (unsigned c = 0; c < 8; ++c) config |= unsigned(sign(s, x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2))) << c;
    return config;
}

/// A grid edge of the 3^3 samples: its start and axis.
using EdgeId = std::array<int, 4>;

/// The unit cell qualifies as a leaf child: no surface, or one component with no face whose
/// corners alternate.
bool unit_cell_qualifies(unsigned config) {
    const McCase& c = mc_case(config);
    std::vector<int> parent(c.triangle_count);
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int i) {
        while (parent[i] != i) i = parent[i];
        return i;
    };
    std::map<int, int> owner;
    for (int t = 0; t < c.triangle_count; ++t) {
        for (int k = 0; k < 3; ++k) {
            const auto [it, fresh] = owner.emplace(c.triangles[t][k], t);
            if (!fresh) parent[find(t)] = find(it->second);
        }
    }
    int components = 0;
    for (int t = 0; t < c.triangle_count; ++t) components += find(t) == t;
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            std::array<int, 4> corner{};
            for (int k = 0; k < 4; ++k) {
                std::array<int, 3> p{};
                p[axis] = side;
                p[(axis + 1) % 3] = k & 1;
                p[(axis + 2) % 3] = k >> 1;
                corner[std::size_t(k)] = int((config >> (p[0] | p[1] << 1 | p[2] << 2)) & 1);
            }
            if (corner[0] == corner[3] && corner[1] == corner[2] && corner[0] != corner[1]) return false;
        }
    }
    return components <= 1;
}

/// Whether the Marching Cubes surface of the 8 unit cells is one disk meeting each of the
/// cell's 12 edges at most once and each of its 6 faces in at most one chain.
bool oracle_one_disk(const Signs& s) {
    // Edges of the cell: at most one sign change along the three samples.
    for (int axis = 0; axis < 3; ++axis) {
        for (int u : {0, 2}) {
            for (int w : {0, 2}) {
                std::array<int, 3> p{};
                int changes = 0;
                for (int a = 0; a < 2; ++a) {
                    p[axis] = a;
                    p[(axis + 1) % 3] = u;
                    p[(axis + 2) % 3] = w;
                    std::array<int, 3> q = p;
                    ++q[axis];
                    changes += sign(s, p[0], p[1], p[2]) != sign(s, q[0], q[1], q[2]);
                }
                if (changes > 1) return false;
            }
        }
    }
    // The surface, welded by grid edge.
    std::vector<std::array<EdgeId, 3>> triangles;
    for (int x = 0; x < 2; ++x) {
        for (int y = 0; y < 2; ++y) {
            for (int z = 0; z < 2; ++z) {
                const McCase& c = mc_case(unit_config(s, x, y, z));
                for (int t = 0; t < c.triangle_count; ++t) {
                    std::array<EdgeId, 3> triangle;
                    for (int k = 0; k < 3; ++k) {
                        const unsigned c0 = kEdgeCorners[c.triangles[t][k]][0], c1 = kEdgeCorners[c.triangles[t][k]][1];
                        const int axis = (c0 ^ c1) == 1 ? 0 : (c0 ^ c1) == 2 ? 1 : 2;
                        triangle[std::size_t(k)] = {x + int(c0 & 1), y + int((c0 >> 1) & 1), z + int(c0 >> 2), axis};
                    }
                    triangles.push_back(triangle);
                }
            }
        }
    }
    if (triangles.empty()) return false;
    std::set<EdgeId> vertices;
    std::map<std::pair<EdgeId, EdgeId>, int> edge_uses;
    for (const auto& t : triangles) {
        for (int k = 0; k < 3; ++k) {
            vertices.insert(t[std::size_t(k)]);
            auto e = std::minmax(t[std::size_t(k)], t[std::size_t((k + 1) % 3)]);
            ++edge_uses[{e.first, e.second}];
        }
    }
    // Components over shared vertices.
    std::map<EdgeId, EdgeId> parent;
    for (const auto& v : vertices) parent[v] = v;
    std::function<EdgeId(EdgeId)> find = [&](EdgeId v) { return parent[v] == v ? v : parent[v] = find(parent[v]); };
    for (const auto& t : triangles) {
        parent[find(t[1])] = find(t[0]);
        parent[find(t[2])] = find(t[0]);
    }
    int components = 0;
    for (const auto& v : vertices) components += find(v) == v;
    const int euler = int(vertices.size()) - int(edge_uses.size()) + int(triangles.size());
    if (components != 1 || euler != 1) return false;
    // Faces of the cell: the boundary edges on each face are one path or nothing.
    for (int axis = 0; axis < 3; ++axis) {
        for (int side : {0, 2}) {
            std::map<EdgeId, int> degree;
            int segments = 0;
            for (const auto& [edge, uses] : edge_uses) {
                if (uses != 1) continue;
                const auto& [a, b] = edge;
                auto on_face = [&](const EdgeId& v) { return v[std::size_t(axis)] == side && v[3] != axis; };
                if (!on_face(a) || !on_face(b)) continue;
                ++segments;
                ++degree[a];
                ++degree[b];
            }
            int ends = 0;
            for (const auto& [v, d] : degree) ends += d == 1;
            // One path: segments + 1 points, two ends; nothing: no segment.
            if (segments != 0 && (ends != 2 || int(degree.size()) != segments + 1)) return false;
        }
    }
    return true;
}

TEST(IfcTopologyTest, TheSignTestAgreesWithTheMarchingCubesSurface) {
    std::mt19937 random(11);
    int checked = 0, disks = 0;
    for (int trial = 0; trial < 400000 && checked < 60000; ++trial) {
        // Random planes and spheres cut through the cell give the patterns real surfaces make;
        // uniform random signs the rest.
        Signs signs;
        std::uniform_real_distribution<double> uniform(-1.0, 1.0);
        const int kind = trial % 3;
        const std::array<double, 4> c = {uniform(random), uniform(random), uniform(random), uniform(random)};
        const double r = 0.5 + uniform(random);
        for (int i = 0; i < 27; ++i) {
            const double x = i / 9 - 1.0, y = (i / 3) % 3 - 1.0, z = i % 3 - 1.0;
            if (kind == 0) signs[std::size_t(i)] = c[0] * x + c[1] * y + c[2] * z + c[3] > 0;
            else if (kind == 1) signs[std::size_t(i)] = (x - c[0]) * (x - c[0]) + (y - c[1]) * (y - c[1]) + (z - c[2]) * (z - c[2]) < r * r;
            else signs[std::size_t(i)] = uniform(random) > c[3];
        }
        std::array<bool, 8> surface{};
        bool qualifies = true;
        for (int child = 0; child < 8; ++child) {
            const unsigned config = unit_config(signs, child & 1, (child >> 1) & 1, child >> 2);
            qualifies &= unit_cell_qualifies(config);
            surface[std::size_t(child)] = config != 0 && config != 255;
        }
        if (!qualifies || std::none_of(surface.begin(), surface.end(), [](bool b) { return b; })) continue;
        const ChildCornerSigns bits = child_corner_signs([&](int x, int y, int z) { return sign(signs, x, y, z); });
        const bool expected = oracle_one_disk(signs);
        ASSERT_EQ(union_is_one_disk(bits, surface), expected) << "trial " << trial;
        ++checked;
        disks += expected;
    }
    // Both answers must have been exercised many times.
    EXPECT_GE(checked, 20000);
    EXPECT_GE(disks, 5000);
    EXPECT_GE(checked - disks, 1000);
}

}  // namespace
}  // namespace vdbmesh::detail
