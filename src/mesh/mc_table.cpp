// The Marching Cubes case table (Lorensen and Cline, "Marching Cubes", SIGGRAPH 1987), generated
// at static initialisation instead of typed in, so that ambiguous faces are resolved by one rule
// that both cells sharing a face apply identically (the face-based disambiguation of Dürst 1988
// and Nielson and Hamann 1991, with a fixed choice instead of the asymptotic decider).
//
// For every configuration of the 8 corners:
//  1. On each of the 6 faces, the edges whose corners differ are joined by segments. With two
//     crossings there is one segment. With four (an ambiguous face: inside corners on one
//     diagonal) each inside corner is cut off by its own segment: inside corners are never
//     joined across a face, outside corners always are. The rule reads only the face's corners.
//  2. Each segment is directed so that, seen from outside the cube, the outside corners lie to
//     its left; the segments then chain into closed loops on the cube's surface, each loop
//     running counter-clockwise around the outside region. Triangles spanning such a loop
//     wind counter-clockwise seen from the outside of the object (their normals point from
//     inside corners to outside ones).
//  3. Each loop is triangulated by dynamic programming over its triangulations, maximising the
//     smallest triangle quality (computed on edge midpoints) and never using a diagonal whose
//     ends lie on one cube face: such a diagonal would run across the face and could coincide
//     with a segment or diagonal of the neighbouring cell.

#include "mesh/mc_table.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <vector>

namespace vdbmesh::detail {

// Edges 0-3 run along x, 4-7 along y, 8-11 along z; within an axis they are ordered by their
// minimum corner.
const std::array<std::array<std::uint8_t, 2>, 12> kEdgeCorners = {{
    {0, 1}, {2, 3}, {4, 5}, {6, 7},
    {0, 2}, {1, 3}, {4, 6}, {5, 7},
    {0, 4}, {1, 5}, {2, 6}, {3, 7},
}};

namespace {

using Point = std::array<double, 3>;

Point corner_position(unsigned corner) {
    return {double(corner & 1), double((corner >> 1) & 1), double((corner >> 2) & 1)};
}

Point edge_midpoint(unsigned edge) {
    const Point a = corner_position(kEdgeCorners[edge][0]);
    const Point b = corner_position(kEdgeCorners[edge][1]);
    return {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
}

Point sub(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Point cross(const Point& a, const Point& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

int edge_between(unsigned a, unsigned b) {
    for (int e = 0; e < 12; ++e) {
        if ((kEdgeCorners[e][0] == a && kEdgeCorners[e][1] == b) ||
            (kEdgeCorners[e][0] == b && kEdgeCorners[e][1] == a)) {
            return e;
        }
    }
    return -1;
}

/// A face of the cube: the corners whose coordinate @a axis equals @a side, in cyclic order.
struct Face {
    std::array<unsigned, 4> corners;
    Point normal;  ///< outward
};

std::array<Face, 6> make_faces() {
    std::array<Face, 6> faces{};
    for (unsigned axis = 0; axis < 3; ++axis) {
        const unsigned u = 1u << ((axis + 1) % 3);
        const unsigned v = 1u << ((axis + 2) % 3);
        for (unsigned side = 0; side < 2; ++side) {
            const unsigned base = side << axis;
            Face& face = faces[2 * axis + side];
            face.corners = {base, base | u, base | u | v, base | v};
            face.normal = {0, 0, 0};
            face.normal[axis] = side ? 1.0 : -1.0;
        }
    }
    return faces;
}

bool inside(unsigned config, unsigned corner) { return (config >> corner) & 1; }

/// The directed segments (from edge, to edge) the face rule puts on @a face.
std::vector<std::array<int, 2>> face_segments(unsigned config, const Face& face) {
    const auto& c = face.corners;
    std::vector<std::array<int, 2>> segments;
    bool ambiguous = inside(config, c[0]) == inside(config, c[2]) &&
                     inside(config, c[1]) == inside(config, c[3]) &&
                     inside(config, c[0]) != inside(config, c[1]);
    if (ambiguous) {
        // Cut off each inside corner by the segment joining its two face edges.
        for (int i = 0; i < 4; ++i) {
            if (!inside(config, c[i])) continue;
            segments.push_back({edge_between(c[(i + 3) % 4], c[i]), edge_between(c[i], c[(i + 1) % 4])});
        }
    } else {
        std::vector<int> crossings;
        for (int i = 0; i < 4; ++i) {
            if (inside(config, c[i]) != inside(config, c[(i + 1) % 4])) {
                crossings.push_back(edge_between(c[i], c[(i + 1) % 4]));
            }
        }
        assert(crossings.size() == 0 || crossings.size() == 2);
        if (crossings.size() == 2) segments.push_back({crossings[0], crossings[1]});
    }
    // Direct each segment so that, seen from outside the cube, outside corners are on its left.
    for (auto& segment : segments) {
        const Point p = edge_midpoint(segment[0]);
        const Point left = cross(face.normal, sub(edge_midpoint(segment[1]), p));
        const unsigned probe = kEdgeCorners[segment[0]][0];
        const bool probe_left = dot(left, sub(corner_position(probe), p)) > 0;
        if (probe_left == inside(config, probe)) std::swap(segment[0], segment[1]);
    }
    return segments;
}

/// Closed loops of edges on the cube's surface, each in the order its segments run.
std::vector<std::vector<int>> chain_loops(unsigned config) {
    static const std::array<Face, 6> faces = make_faces();
    std::array<int, 12> next;
    next.fill(-1);
    for (const Face& face : faces) {
        for (const auto& segment : face_segments(config, face)) {
            assert(next[segment[0]] == -1);
            next[segment[0]] = segment[1];
        }
    }
    std::vector<std::vector<int>> loops;
    std::array<bool, 12> used{};
    for (int start = 0; start < 12; ++start) {
        if (next[start] < 0 || used[start]) continue;
        std::vector<int> loop;
        for (int e = start; !used[e]; e = next[e]) {
            used[e] = true;
            loop.push_back(e);
        }
        loops.push_back(loop);
    }
    return loops;
}

bool share_face(int edge_a, int edge_b) {
    // Two edges lie on a common face when their four corners span only two coordinates.
    const unsigned all_or = kEdgeCorners[edge_a][0] | kEdgeCorners[edge_a][1] | kEdgeCorners[edge_b][0] |
                            kEdgeCorners[edge_b][1];
    const unsigned all_and = kEdgeCorners[edge_a][0] & kEdgeCorners[edge_a][1] & kEdgeCorners[edge_b][0] &
                             kEdgeCorners[edge_b][1];
    return (~all_or & 7u) != 0 || all_and != 0;
}

/// Triangle quality in [0, 1]: 4 sqrt(3) area / (sum of squared edge lengths), 1 if equilateral.
double triangle_quality(int a, int b, int c) {
    const Point pa = edge_midpoint(a), pb = edge_midpoint(b), pc = edge_midpoint(c);
    const Point n = cross(sub(pb, pa), sub(pc, pa));
    const double area = 0.5 * std::sqrt(dot(n, n));
    const double lengths = dot(sub(pb, pa), sub(pb, pa)) + dot(sub(pc, pb), sub(pc, pb)) +
                           dot(sub(pa, pc), sub(pa, pc));
    return 4.0 * std::sqrt(3.0) * area / lengths;
}

/// Triangulates @a loop (kept in order, so the triangles keep its winding), maximising the
/// smallest triangle quality; appends to @a out.
void triangulate_loop(const std::vector<int>& loop, McCase& out) {
    const int n = int(loop.size());
    constexpr double kForbidden = -1.0;
    // best[i][j]: the best smallest quality triangulating the sub-polygon loop[i..j]; split[i][j]
    // the apex k of the triangle on the side (i, j).
    std::vector<std::vector<double>> best(n, std::vector<double>(n, 1e9));
    std::vector<std::vector<int>> split(n, std::vector<int>(n, -1));
    auto side_allowed = [&](int i, int j) {
        return j - i == 1 || (i == 0 && j == n - 1) || !share_face(loop[i], loop[j]);
    };
    for (int length = 2; length < n; ++length) {
        for (int i = 0; i + length < n; ++i) {
            const int j = i + length;
            best[i][j] = kForbidden;
            if (!side_allowed(i, j)) continue;
            for (int k = i + 1; k < j; ++k) {
                if (best[i][k] == kForbidden || best[k][j] == kForbidden) continue;
                const double q = std::min({best[i][k], best[k][j], triangle_quality(loop[i], loop[k], loop[j])});
                if (q > best[i][j]) {
                    best[i][j] = q;
                    split[i][j] = k;
                }
            }
        }
    }
    assert(best[0][n - 1] > 0);
    std::vector<std::array<int, 2>> stack = {{0, n - 1}};
    while (!stack.empty()) {
        const auto [i, j] = stack.back();
        stack.pop_back();
        if (j - i < 2) continue;
        const int k = split[i][j];
        assert(out.triangle_count < out.triangles.size());
        out.triangles[out.triangle_count++] = {std::uint8_t(loop[i]), std::uint8_t(loop[k]), std::uint8_t(loop[j])};
        stack.push_back({i, k});
        stack.push_back({k, j});
    }
}

std::array<McCase, 256> build_cases() {
    std::array<McCase, 256> cases{};
    for (unsigned config = 0; config < 256; ++config) {
        for (const auto& loop : chain_loops(config)) triangulate_loop(loop, cases[config]);
    }
    return cases;
}

}  // namespace

const McCase& mc_case(unsigned config) {
    static const std::array<McCase, 256> cases = build_cases();
    return cases[config & 255u];
}

}  // namespace vdbmesh::detail
