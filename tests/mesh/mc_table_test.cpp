// Checks the generated Marching Cubes table case by case: coverage of the crossing edges,
// closed loops, the face rule, agreement between face neighbours and complements, orientation.

#include <gtest/gtest.h>

#include <array>
#include <map>
#include <set>
#include <utility>

#include "mesh/mc_table.h"

namespace vdbmesh::detail {
namespace {

using Segment = std::pair<int, int>;  // directed, from edge to edge

bool is_inside(unsigned config, unsigned corner) { return (config >> corner) & 1; }

bool edge_crosses(unsigned config, int edge) {
    return is_inside(config, kEdgeCorners[edge][0]) != is_inside(config, kEdgeCorners[edge][1]);
}

/// The directed edges of the case's triangles that no triangle uses in reverse.
std::set<Segment> boundary_segments(unsigned config) {
    std::map<Segment, int> count;
    const McCase& c = mc_case(config);
    for (int t = 0; t < c.triangle_count; ++t) {
        for (int i = 0; i < 3; ++i) ++count[{c.triangles[t][i], c.triangles[t][(i + 1) % 3]}];
    }
    std::set<Segment> boundary;
    for (const auto& [segment, n] : count) {
        EXPECT_EQ(n, 1) << "config " << config << " repeats a directed edge";
        if (!count.count({segment.second, segment.first})) boundary.insert(segment);
    }
    return boundary;
}

/// The face (axis, side) holds the edge when both its corners have coordinate @a side on @a axis.
bool edge_on_face(int edge, unsigned axis, unsigned side) {
    const unsigned bit = 1u << axis;
    return ((kEdgeCorners[edge][0] & bit) != 0) == bool(side) && ((kEdgeCorners[edge][1] & bit) != 0) == bool(side);
}

std::set<Segment> segments_on_face(const std::set<Segment>& segments, unsigned axis, unsigned side) {
    std::set<Segment> on_face;
    for (const auto& s : segments) {
        if (edge_on_face(s.first, axis, side) && edge_on_face(s.second, axis, side)) on_face.insert(s);
    }
    return on_face;
}

int edge_with_corners(unsigned a, unsigned b) {
    for (int e = 0; e < 12; ++e) {
        if (std::min(a, b) == kEdgeCorners[e][0] && std::max(a, b) == kEdgeCorners[e][1]) return e;
    }
    return -1;
}

/// The same edge seen from the cell next door along @a axis (corners flipped on that axis).
int mirror_edge(int edge, unsigned axis) {
    const unsigned bit = 1u << axis;
    return edge_with_corners(kEdgeCorners[edge][0] ^ bit, kEdgeCorners[edge][1] ^ bit);
}

/// The corner configuration restricted to face (axis, side), as a 4-bit key in corner order.
unsigned face_key(unsigned config, unsigned axis, unsigned side) {
    unsigned key = 0, n = 0;
    for (unsigned corner = 0; corner < 8; ++corner) {
        if (((corner >> axis) & 1) == side) key |= unsigned(is_inside(config, corner)) << n++;
    }
    return key;
}

TEST(McTableTest, EveryCrossingEdgeIsUsedAndNoOther) {
    for (unsigned config = 0; config < 256; ++config) {
        const McCase& c = mc_case(config);
        std::set<int> used;
        for (int t = 0; t < c.triangle_count; ++t) {
            const auto& tri = c.triangles[t];
            EXPECT_TRUE(tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2]) << "config " << config;
            used.insert(tri.begin(), tri.end());
        }
        for (int e = 0; e < 12; ++e) EXPECT_EQ(used.count(e) == 1, edge_crosses(config, e)) << config << " " << e;
    }
    EXPECT_EQ(mc_case(0).triangle_count, 0);
    EXPECT_EQ(mc_case(255).triangle_count, 0);
    EXPECT_EQ(mc_case(1).triangle_count, 1);
}

TEST(McTableTest, BoundaryIsClosedLoopsOnTheFaces) {
    for (unsigned config = 0; config < 256; ++config) {
        const std::set<Segment> boundary = boundary_segments(config);
        std::array<int, 12> out{}, in{};
        for (const auto& s : boundary) {
            ++out[s.first];
            ++in[s.second];
            bool on_some_face = false;
            for (unsigned axis = 0; axis < 3; ++axis) {
                for (unsigned side = 0; side < 2; ++side) {
                    on_some_face |= edge_on_face(s.first, axis, side) && edge_on_face(s.second, axis, side);
                }
            }
            EXPECT_TRUE(on_some_face) << "config " << config << " segment " << s.first << "-" << s.second;
        }
        for (int e = 0; e < 12; ++e) {
            const int expected = edge_crosses(config, e) ? 1 : 0;
            EXPECT_EQ(out[e], expected) << "config " << config << " edge " << e;
            EXPECT_EQ(in[e], expected) << "config " << config << " edge " << e;
        }
    }
}

TEST(McTableTest, FacesFollowTheRuleInsideCornersNeverJoined) {
    for (unsigned config = 0; config < 256; ++config) {
        const std::set<Segment> boundary = boundary_segments(config);
        for (unsigned axis = 0; axis < 3; ++axis) {
            for (unsigned side = 0; side < 2; ++side) {
                const std::set<Segment> on_face = segments_on_face(boundary, axis, side);
                int crossings = 0;
                for (int e = 0; e < 12; ++e) crossings += edge_on_face(e, axis, side) && edge_crosses(config, e);
                ASSERT_EQ(int(on_face.size()), crossings / 2) << "config " << config;
                if (crossings != 4) continue;
                // Ambiguous face: each segment cuts off one inside corner (its two edges share it).
                for (const auto& s : on_face) {
                    const auto& a = kEdgeCorners[s.first];
                    const auto& b = kEdgeCorners[s.second];
                    const int shared = (a[0] == b[0] || a[0] == b[1]) ? a[0] : (a[1] == b[0] || a[1] == b[1]) ? a[1] : -1;
                    ASSERT_GE(shared, 0) << "config " << config;
                    EXPECT_TRUE(is_inside(config, unsigned(shared))) << "config " << config;
                }
            }
        }
    }
}

TEST(McTableTest, FaceNeighboursAgreeWithOppositeDirections) {
    int pairs = 0;
    for (unsigned axis = 0; axis < 3; ++axis) {
        for (unsigned a = 0; a < 256; ++a) {
            const std::set<Segment> a_face = segments_on_face(boundary_segments(a), axis, 1);
            for (unsigned b = 0; b < 256; ++b) {
                if (face_key(a, axis, 1) != face_key(b, axis, 0)) continue;
                const std::set<Segment> b_face = segments_on_face(boundary_segments(b), axis, 0);
                std::set<Segment> mirrored_reversed;
                for (const auto& s : a_face) mirrored_reversed.insert({mirror_edge(s.second, axis), mirror_edge(s.first, axis)});
                ASSERT_EQ(mirrored_reversed, b_face) << "axis " << axis << " configs " << a << ", " << b;
                ++pairs;
            }
        }
    }
    EXPECT_EQ(pairs, 3 * 256 * 16);
}

TEST(McTableTest, ComplementReversesBoundaryWhenNoFaceIsAmbiguous) {
    int checked = 0;
    for (unsigned config = 0; config < 256; ++config) {
        bool ambiguous = false;
        for (unsigned axis = 0; axis < 3; ++axis) {
            for (unsigned side = 0; side < 2; ++side) {
                const unsigned key = face_key(config, axis, side);
                // Corners in key order 0,1,2,3 sit at (0,0),(1,0),(0,1),(1,1): diagonals are 0-3, 1-2.
                ambiguous |= key == 0b1001 || key == 0b0110;
            }
        }
        if (ambiguous) continue;
        std::set<Segment> reversed;
        for (const auto& s : boundary_segments(config)) reversed.insert({s.second, s.first});
        EXPECT_EQ(reversed, boundary_segments(~config & 255u)) << "config " << config;
        ++checked;
    }
    EXPECT_GT(checked, 100);
}

TEST(McTableTest, NormalsPointFromInsideToOutside) {
    auto midpoint = [](int edge) {
        std::array<double, 3> p{};
        for (unsigned corner : kEdgeCorners[edge]) {
            for (int axis = 0; axis < 3; ++axis) p[axis] += 0.5 * ((corner >> axis) & 1);
        }
        return p;
    };
    for (unsigned config = 0; config < 256; ++config) {
        const McCase& c = mc_case(config);
        for (int t = 0; t < c.triangle_count; ++t) {
            const auto p0 = midpoint(c.triangles[t][0]), p1 = midpoint(c.triangles[t][1]), p2 = midpoint(c.triangles[t][2]);
            const std::array<double, 3> u{p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
            const std::array<double, 3> v{p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
            const std::array<double, 3> normal{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
            // Sum over the triangle's edges of the direction from their inside corner to their outside one.
            double outward = 0;
            for (int edge : c.triangles[t]) {
                const unsigned a = kEdgeCorners[edge][0], b = kEdgeCorners[edge][1];
                const double sign = is_inside(config, a) ? 1.0 : -1.0;
                const unsigned axis = (a ^ b) == 1 ? 0 : (a ^ b) == 2 ? 1 : 2;
                outward += sign * normal[axis];
            }
            EXPECT_GT(outward, 0) << "config " << config << " triangle " << t;
        }
    }
}

}  // namespace
}  // namespace vdbmesh::detail
