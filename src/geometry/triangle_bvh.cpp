// A linear bounding-volume hierarchy over triangles (see geometry.h) and the exact
// closest point on a triangle.
#include "vdbmesh/geometry.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace vdbmesh::detail {
namespace {

Point3 to_point(const std::array<float, 3>& v) { return {v[0], v[1], v[2]}; }

Box merge(const Box& a, const Box& b) {
    Box box;
    for (int k = 0; k < 3; ++k) {
        box.lo[k] = std::min(a.lo[k], b.lo[k]);
        box.hi[k] = std::max(a.hi[k], b.hi[k]);
    }
    return box;
}

}  // namespace

std::uint64_t spread_bits(std::uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

namespace {

/// Squared distance from p to the box (0 inside).
double box_distance_squared(const Point3& p, const Box& box) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
        const double below = box.lo[k] - p[k], above = p[k] - box.hi[k];
        const double d = std::max({below, above, 0.0});
        d2 += d * d;
    }
    return d2;
}

double dot(const Point3& a, const Point3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Point3 minus(const Point3& a, const Point3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Point3 along(const Point3& a, const Point3& d, double t) { return {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]}; }

}  // namespace

Box triangle_box(const Mesh& mesh, std::uint32_t triangle) {
    const auto& t = mesh.triangles[triangle];
    Box box{mesh.vertices[t[0]], mesh.vertices[t[0]]};
    for (int corner = 1; corner < 3; ++corner) {
        const auto& v = mesh.vertices[t[corner]];
        for (int k = 0; k < 3; ++k) {
            box.lo[k] = std::min(box.lo[k], v[k]);
            box.hi[k] = std::max(box.hi[k], v[k]);
        }
    }
    return box;
}

Point3 closest_point_on_triangle(const Point3& p, const Point3& a, const Point3& b, const Point3& c) {
    const Point3 ab = minus(b, a), ac = minus(c, a), ap = minus(p, a);
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Point3 bp = minus(p, b);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return along(a, ab, d1 / (d1 - d3));
    const Point3 cp = minus(p, c);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return along(a, ac, d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        return along(b, minus(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    const double denominator = va + vb + vc;
    if (!(denominator > 0)) return a;  // degenerate triangle reached through rounding
    const double v = vb / denominator, w = vc / denominator;
    return {a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w};
}

TriangleBvh::TriangleBvh(const Mesh& mesh, std::vector<std::uint32_t> triangles)
    : mesh_(&mesh), order_(std::move(triangles)) {
    if (order_.empty()) return;
    const std::size_t n = order_.size();
    std::vector<Box> boxes(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) { boxes[i] = triangle_box(mesh, order_[i]); });

    // Morton codes of the box centres within the bounding box of all centres.
    Box bounds = boxes[0];
    for (const Box& box : boxes) bounds = merge(bounds, box);
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
        std::uint64_t code = 0;
        for (int k = 0; k < 3; ++k) {
            const double extent = double(bounds.hi[k]) - bounds.lo[k];
            const double centre = 0.5 * (double(boxes[i].lo[k]) + boxes[i].hi[k]);
            const double unit = extent > 0 ? (centre - bounds.lo[k]) / extent : 0.0;
            code |= spread_bits(std::uint64_t(std::clamp(unit, 0.0, 1.0) * 2097151.0)) << k;
        }
        keyed[i] = {code, std::uint32_t(i)};
    });
    tbb::parallel_sort(keyed.begin(), keyed.end());  // ties broken by position: deterministic

    boxes_.resize(n);
    std::vector<std::uint32_t> sorted_order(n);
    std::vector<std::uint64_t> codes(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
        boxes_[i] = boxes[keyed[i].second];
        sorted_order[i] = order_[keyed[i].second];
        codes[i] = keyed[i].first;
    });
    order_ = std::move(sorted_order);
    nodes_.reserve(2 * (n / kLeafSize + 1));
    build(0, std::uint32_t(n), codes);
}

std::uint32_t TriangleBvh::build(std::uint32_t begin, std::uint32_t end, const std::vector<std::uint64_t>& codes) {
    const std::uint32_t index = std::uint32_t(nodes_.size());
    nodes_.emplace_back();
    if (end - begin <= kLeafSize) {
        Box box = boxes_[begin];
        for (std::uint32_t i = begin + 1; i < end; ++i) box = merge(box, boxes_[i]);
        nodes_[index] = {box, begin, end, 0};
        leaves_.push_back(index);
        return index;
    }
    // Split after the last code that agrees with the first one on the highest bit where the
    // range's first and last codes differ; halve a range of equal codes.
    std::uint32_t middle = begin + (end - begin) / 2;
    const std::uint64_t first = codes[begin], last = codes[end - 1];
    if (first != last) {
        const int bit = 63 - __builtin_clzll(first ^ last);
        const std::uint64_t mask = ~0ULL << bit;  // the bits at and above the differing one
        middle = std::uint32_t(std::partition_point(codes.begin() + begin, codes.begin() + end,
                                                    [&](std::uint64_t c) { return (c & mask) == (first & mask); }) -
                               codes.begin());
    }
    const std::uint32_t left = build(begin, middle, codes);
    const std::uint32_t right = build(middle, end, codes);
    nodes_[index] = {merge(nodes_[left].box, nodes_[right].box), begin, end, right};
    return index;
}

ClosestPoint TriangleBvh::closest_on_triangle(const Point3& p, std::uint32_t triangle) const {
    const auto& t = mesh_->triangles[triangle];
    const Point3 q = closest_point_on_triangle(p, to_point(mesh_->vertices[t[0]]), to_point(mesh_->vertices[t[1]]),
                                               to_point(mesh_->vertices[t[2]]));
    const Point3 d = minus(q, p);
    return {dot(d, d), triangle, q};
}

ClosestPoint TriangleBvh::closest_point(const Point3& p, double bound_squared) const {
    ClosestPoint best;
    best.distance_squared = bound_squared;
    std::uint32_t stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes_[stack[--top]];
        if (box_distance_squared(p, node.box) >= best.distance_squared) continue;
        if (node.right == 0) {
            for (std::uint32_t k = node.begin; k < node.end; ++k) {
                const ClosestPoint candidate = closest_on_triangle(p, order_[k]);
                if (candidate.distance_squared < best.distance_squared) best = candidate;
            }
            continue;
        }
        // Visit the nearer child first (pushed last) so that the far one is often pruned.
        const std::uint32_t index = std::uint32_t(&node - nodes_.data());
        const std::uint32_t left = index + 1, right = node.right;
        const bool left_nearer =
            box_distance_squared(p, nodes_[left].box) <= box_distance_squared(p, nodes_[right].box);
        stack[top++] = left_nearer ? right : left;
        stack[top++] = left_nearer ? left : right;
    }
    return best;
}

}  // namespace vdbmesh::detail
