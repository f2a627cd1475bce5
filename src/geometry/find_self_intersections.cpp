// Self-intersections: candidate pairs from a bounding-volume hierarchy over the triangle
// boxes (geometry.h), each decided exactly (triangle_intersection.h). Corners that share
// a position are the same point (canonical ids), so pairs meeting only where they must
// (a common corner or edge) are not reported.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>

#include "geometry/triangle_intersection.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh {
namespace {

using detail::Point3;
using detail::Triangle3;

class PairTester {
public:
    PairTester(const Mesh& mesh, const std::vector<std::uint32_t>& canonical) : mesh_(mesh), canonical_(canonical) {}

    bool intersect(std::uint32_t first, std::uint32_t second) const {
        const auto& t = mesh_.triangles[first];
        const auto& u = mesh_.triangles[second];
        int shared = 0, t_shared = -1, u_shared = -1;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                if (canonical_[t[i]] != canonical_[u[j]]) continue;
                if (shared == 0) t_shared = i, u_shared = j;
                ++shared;
            }
        }
        switch (shared) {
            case 0: return detail::triangles_meet(corners(t, 0), corners(u, 0));
            case 1: return detail::triangles_meet_beyond_corner(corners(t, t_shared), corners(u, u_shared));
            case 2: return meet_beyond_edge(t, u);
            default: return true;  // the same three points: a duplicated face
        }
    }

private:
    Point3 point(std::uint32_t v) const {
        const auto& p = mesh_.vertices[v];
        return {p[0], p[1], p[2]};
    }

    /// The triangle's corners starting from corner @a first (a rotation: same orientation).
    Triangle3 corners(const std::array<std::uint32_t, 3>& t, int first) const {
        return {point(t[first]), point(t[(first + 1) % 3]), point(t[(first + 2) % 3])};
    }

    bool meet_beyond_edge(const std::array<std::uint32_t, 3>& t, const std::array<std::uint32_t, 3>& u) const {
        const auto is_shared = [&](std::uint32_t v, const std::array<std::uint32_t, 3>& other) {
            return canonical_[v] == canonical_[other[0]] || canonical_[v] == canonical_[other[1]] ||
                   canonical_[v] == canonical_[other[2]];
        };
        int t_apex = 0, u_apex = 0;
        while (is_shared(t[t_apex], u)) ++t_apex;
        while (is_shared(u[u_apex], t)) ++u_apex;
        return detail::triangles_meet_beyond_edge(point(t[(t_apex + 1) % 3]), point(t[(t_apex + 2) % 3]),
                                                  point(t[t_apex]), point(u[u_apex]));
    }

    const Mesh& mesh_;
    const std::vector<std::uint32_t>& canonical_;
};

}  // namespace

std::vector<std::pair<std::uint32_t, std::uint32_t>> find_self_intersections(const Mesh& mesh) {
    using Pair = std::pair<std::uint32_t, std::uint32_t>;
    detail::check_indices(mesh);
    const std::vector<std::uint32_t> regular = detail::regular_faces(detail::classify_faces(mesh));
    const std::vector<std::uint32_t> canonical = detail::canonical_vertices(mesh);
    const detail::TriangleBvh bvh(mesh, regular);
    const PairTester tester(mesh, canonical);

    tbb::enumerable_thread_specific<std::vector<Pair>> found;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, bvh.leaf_count(), 256), [&](const auto& range) {
        std::vector<Pair>& local = found.local();
        for (std::size_t leaf = range.begin(); leaf != range.end(); ++leaf) {
            bvh.visit_overlapping_pairs(leaf, [&](std::uint32_t first, std::uint32_t second) {
                if (tester.intersect(first, second)) local.emplace_back(std::min(first, second), std::max(first, second));
            });
        }
    });
    std::vector<Pair> pairs;
    for (const std::vector<Pair>& local : found) pairs.insert(pairs.end(), local.begin(), local.end());
    std::sort(pairs.begin(), pairs.end());  // thread partition independent
    return pairs;
}

}  // namespace vdbmesh
