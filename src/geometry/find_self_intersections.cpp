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
        return detail::triangles_intersect(ids(t), corners(t), ids(u), corners(u));
    }

private:
    std::array<std::uint32_t, 3> ids(const std::array<std::uint32_t, 3>& t) const {
        return {canonical_[t[0]], canonical_[t[1]], canonical_[t[2]]};
    }

    Triangle3 corners(const std::array<std::uint32_t, 3>& t) const {
        const auto point = [&](std::uint32_t v) {
            const auto& p = mesh_.vertices[v];
            return Point3{p[0], p[1], p[2]};
        };
        return {point(t[0]), point(t[1]), point(t[2])};
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
