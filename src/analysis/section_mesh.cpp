// section_mesh(): the cut of a closed mesh by a plane (shared seed 002, chapter 3: cross-sections
// of the solid). Each triangle that straddles the plane gives one segment between the crossing
// points of its two straddling edges; a vertex on the plane counts as above it (a symbolic
// perturbation), so each crossing edge of a closed, oriented mesh starts exactly one segment and
// ends exactly one, and the segments chain into closed loops. A segment runs from the edge that
// goes down through the plane to the edge that goes up (in the triangle's order), which makes
// outer loops counter-clockwise seen from the normal's side. Figures: section_figures.cpp.
#include <algorithm>
#include <cmath>
#include <string>

#include "analysis/section_figures.h"
#include "vdbmesh/error.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/section.h"

namespace vdbmesh {
namespace {

using Vec = std::array<double, 3>;

/// A directed piece of the cut: from the crossing point of one edge to that of another,
/// each edge named by its vertices (smaller index first).
struct Segment {
    std::uint64_t from, to;
    bool operator<(const Segment& o) const { return from < o.from; }
};

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) { return std::uint64_t(std::min(a, b)) << 32 | std::max(a, b); }

std::string edge_name(std::uint64_t key) {
    return "(" + std::to_string(key >> 32) + ", " + std::to_string(key & 0xffffffffu) + ")";
}

class PlaneCut {
public:
    PlaneCut(const Mesh& mesh, const Plane& plane) : mesh_(mesh), distance_(mesh.vertices.size()) {
        for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
            const auto& p = mesh.vertices[v];
            distance_[v] = plane.normal[0] * p[0] + plane.normal[1] * p[1] + plane.normal[2] * p[2] - plane.offset;
        }
    }

    /// Every segment, sorted by the edge it starts from.
    std::vector<Segment> segments() const {
        std::vector<Segment> result;
        for (const auto& t : mesh_.triangles) {
            std::uint64_t down = 0, up = 0;
            int crossings = 0;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = t[k], b = t[(k + 1) % 3];
                if (above(a) == above(b)) continue;
                ++crossings;
                (above(a) ? down : up) = edge_key(a, b);
            }
            if (crossings == 2) result.push_back({down, up});
        }
        std::sort(result.begin(), result.end());
        return result;
    }

    /// Where the edge @a key crosses the plane (the same bits from either triangle).
    Vec crossing(std::uint64_t key) const {
        const auto a = std::uint32_t(key >> 32), b = std::uint32_t(key);
        const double t = distance_[a] / (distance_[a] - distance_[b]);
        const auto& p = mesh_.vertices[a];
        const auto& q = mesh_.vertices[b];
        return {p[0] + t * (double(q[0]) - p[0]), p[1] + t * (double(q[1]) - p[1]), p[2] + t * (double(q[2]) - p[2])};
    }

private:
    bool above(std::uint32_t v) const { return distance_[v] >= 0; }

    const Mesh& mesh_;
    std::vector<double> distance_;
};

[[noreturn]] void throw_not_closed(std::uint64_t key, const char* what) {
    throw Error("section: the mesh is not closed and consistently oriented where the plane cuts it: the crossing edge " +
                edge_name(key) + " " + what);
}

/// The segments chained into closed loops of crossing points.
std::vector<std::vector<Vec>> chain_loops(const PlaneCut& cut, const std::vector<Segment>& segments) {
    for (std::size_t i = 1; i < segments.size(); ++i) {
        if (segments[i].from == segments[i - 1].from) throw_not_closed(segments[i].from, "goes down through the plane in two triangles");
    }
    std::vector<char> used(segments.size(), 0);
    std::vector<std::vector<Vec>> loops;
    for (std::size_t first = 0; first < segments.size(); ++first) {
        if (used[first]) continue;
        std::vector<Vec> loop;
        for (std::size_t i = first; !used[i];) {
            used[i] = 1;
            loop.push_back(cut.crossing(segments[i].from));
            const auto next = std::lower_bound(segments.begin(), segments.end(), Segment{segments[i].to, 0});
            if (next == segments.end() || next->from != segments[i].to) throw_not_closed(segments[i].to, "goes up through the plane in no other triangle");
            i = std::size_t(next - segments.begin());
        }
        loops.push_back(std::move(loop));
    }
    return loops;
}

}  // namespace

Plane axis_plane(int axis, double value) {
    if (axis < 0 || axis > 2) throw UsageError("plane axis: expected 0, 1 or 2, got " + std::to_string(axis));
    Plane plane;
    plane.normal = {0, 0, 0};
    plane.normal[axis] = 1;
    plane.offset = value;
    return plane;
}

Plane make_plane(const std::array<double, 3>& normal, double offset) {
    const double length = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    if (!(length > 0) || !std::isfinite(length)) throw UsageError("plane normal: expected a finite non-zero vector");
    if (!std::isfinite(offset)) throw UsageError("plane offset: expected a finite number");
    return Plane{{normal[0] / length, normal[1] / length, normal[2] / length}, offset};
}

Section section_mesh(const Mesh& mesh, const Plane& plane) {
    detail::check_indices(mesh);
    const PlaneCut cut(mesh, plane);
    return detail::section_from_loops(plane, chain_loops(cut, cut.segments()));
}

}  // namespace vdbmesh
