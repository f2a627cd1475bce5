// The cut of a mesh by a plane, triangle by triangle: see section_cut.h.
#include "analysis/section_cut.h"

#include <algorithm>
#include <cstring>
#include <sstream>

#include "vdbmesh/error.h"

namespace vdbmesh::detail {
namespace {

using Vec = std::array<double, 3>;
using Position = std::array<float, 3>;

std::array<std::uint32_t, 3> position_bits(const Position& p) {
    std::array<std::uint32_t, 3> bits;
    std::memcpy(bits.data(), p.data(), sizeof bits);
    return bits;
}

[[noreturn]] void throw_not_closed(const EdgeName& edge, bool numbered, const char* what) {
    throw Error("section: the mesh is not closed and consistently oriented where the plane cuts it: the crossing edge " +
                edge_text(edge, numbered) + " " + what);
}

}  // namespace

CutTriangle numbered_triangle(const std::array<std::uint32_t, 3>& vertices, const std::array<Position, 3>& corners) {
    CutTriangle triangle{corners, {}, {}};
    for (int k = 0; k < 3; ++k) {
        const int next = (k + 1) % 3;
        const bool forward = vertices[k] < vertices[next];
        triangle.edges[k] = {std::min(vertices[k], vertices[next]), std::max(vertices[k], vertices[next]), 0, 0, 0, 0};
        triangle.first_end[k] = forward ? k : next;
    }
    return triangle;
}

CutTriangle positioned_triangle(const std::array<Position, 3>& corners) {
    CutTriangle triangle{corners, {}, {}};
    for (int k = 0; k < 3; ++k) {
        const int next = (k + 1) % 3;
        const auto a = position_bits(corners[k]), b = position_bits(corners[next]);
        const bool forward = a < b;
        const auto& first = forward ? a : b;
        const auto& second = forward ? b : a;
        triangle.edges[k] = {first[0], first[1], first[2], second[0], second[1], second[2]};
        triangle.first_end[k] = forward ? k : next;
    }
    return triangle;
}

void cut_triangle(const Plane& plane, const CutTriangle& triangle, std::vector<CutSegment>& segments) {
    std::array<double, 3> distance;
    for (int k = 0; k < 3; ++k) {
        const Position& p = triangle.corners[k];
        distance[k] = plane.normal[0] * p[0] + plane.normal[1] * p[1] + plane.normal[2] * p[2] - plane.offset;
    }
    const auto above = [&](int k) { return distance[k] >= 0; };
    int down = -1, up = -1, crossings = 0;
    for (int k = 0; k < 3; ++k) {
        const int next = (k + 1) % 3;
        if (above(k) == above(next)) continue;
        ++crossings;
        (above(k) ? down : up) = k;
    }
    if (crossings != 2) return;
    // Where the edge `down` crosses, measured from its name's first end.
    const int a = triangle.first_end[down], b = a == down ? (down + 1) % 3 : down;
    const double t = distance[a] / (distance[a] - distance[b]);
    const Position &p = triangle.corners[a], &q = triangle.corners[b];
    const Vec start{p[0] + t * (double(q[0]) - p[0]), p[1] + t * (double(q[1]) - p[1]), p[2] + t * (double(q[2]) - p[2])};
    segments.push_back({triangle.edges[down], triangle.edges[up], start});
}

std::string edge_text(const EdgeName& edge, bool numbered) {
    if (numbered) return "(" + std::to_string(edge[0]) + ", " + std::to_string(edge[1]) + ")";
    std::ostringstream text;
    text.precision(9);
    for (int end = 0; end < 2; ++end) {
        float p[3];
        std::memcpy(p, &edge[3 * end], sizeof p);
        text << (end == 0 ? "(" : "-(") << p[0] << " " << p[1] << " " << p[2] << ")";
    }
    return text.str();
}

std::vector<std::vector<Vec>> chain_loops(std::vector<CutSegment> segments, bool numbered) {
    std::sort(segments.begin(), segments.end());
    for (std::size_t i = 1; i < segments.size(); ++i) {
        if (segments[i].from == segments[i - 1].from) throw_not_closed(segments[i].from, numbered, "goes down through the plane in two triangles");
    }
    std::vector<char> used(segments.size(), 0);
    std::vector<std::vector<Vec>> loops;
    for (std::size_t first = 0; first < segments.size(); ++first) {
        if (used[first]) continue;
        std::vector<Vec> loop;
        for (std::size_t i = first; !used[i];) {
            used[i] = 1;
            loop.push_back(segments[i].start);
            const auto next = std::lower_bound(segments.begin(), segments.end(), CutSegment{segments[i].to, {}, {}});
            if (next == segments.end() || next->from != segments[i].to) {
                throw_not_closed(segments[i].to, numbered, "goes up through the plane in no other triangle");
            }
            i = std::size_t(next - segments.begin());
        }
        loops.push_back(std::move(loop));
    }
    return loops;
}

}  // namespace vdbmesh::detail
