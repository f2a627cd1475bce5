#pragma once
// Private: a bounding-volume hierarchy over a mesh's triangles, for overlap and
// closest-point queries.

#include <array>
#include <cstdint>
#include <vector>

#include "analysis/exact_predicates.h"
#include "vdbmesh/mesh.h"

namespace vdbmesh::detail {

/// An axis-aligned box; float is exact since mesh coordinates are floats.
struct Box {
    std::array<float, 3> lo, hi;
};

Box triangle_box(const Mesh& mesh, std::uint32_t triangle);

inline bool boxes_overlap(const Box& a, const Box& b) {
    for (int k = 0; k < 3; ++k) {
        if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
    }
    return true;
}

/// The closest point of a mesh to a query point.
struct ClosestPoint {
    double distance_squared = 0;
    std::uint32_t triangle = 0;
    Point3 point{};
};

/// Closest point of triangle abc to p (exact up to rounding: the region of the triangle that
/// is closest is found from barycentric signs, after C. Ericson, Real-Time Collision
/// Detection, 2005, section 5.1.5).
Point3 closest_point_on_triangle(const Point3& p, const Point3& a, const Point3& b, const Point3& c);

/// A binary tree over the triangles sorted along a Morton (Z-order) curve of their box centres,
/// each node splitting its range where the highest differing Morton bit changes (a linear BVH:
/// T. Karras, "Maximizing parallelism in the construction of BVHs, octrees, and k-d trees",
/// HPG 2012, built top-down), or in halves among equal codes.
class TriangleBvh {
public:
    /// Over the listed triangles of @a mesh (which must outlive the tree).
    TriangleBvh(const Mesh& mesh, std::vector<std::uint32_t> triangles);

    /// Calls visit(triangle) for every listed triangle whose box overlaps @a query (closed boxes).
    template <class Visit>
    void visit_overlaps(const Box& query, Visit&& visit) const;

    /// The closest point of the listed triangles to @a p; requires at least one triangle.
    ClosestPoint closest_point(const Point3& p) const;

    bool empty() const { return nodes_.empty(); }

private:
    struct Node {
        Box box;
        std::uint32_t first = 0;  ///< leaf: first index in order_; inner: index of the right child
        std::uint32_t count = 0;  ///< leaf: number of triangles; inner: 0 (left child follows)
    };
    static constexpr int kLeafSize = 4;
    // 63 levels of Morton bits, then halving at most 2^32 equal codes.
    static constexpr int kMaxDepth = 100;

    std::uint32_t build(std::uint32_t begin, std::uint32_t end, const std::vector<std::uint64_t>& codes);

    const Mesh* mesh_;
    std::vector<std::uint32_t> order_;  ///< triangles in Morton order
    std::vector<Box> boxes_;            ///< their boxes, in the same order
    std::vector<Node> nodes_;
};

template <class Visit>
void TriangleBvh::visit_overlaps(const Box& query, Visit&& visit) const {
    if (nodes_.empty()) return;
    std::uint32_t stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const std::uint32_t index = stack[--top];
        const Node& node = nodes_[index];
        if (!boxes_overlap(node.box, query)) continue;
        if (node.count > 0) {
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
                if (boxes_overlap(boxes_[k], query)) visit(order_[k]);
            }
        } else {
            stack[top++] = node.first;
            stack[top++] = index + 1;
        }
    }
}

}  // namespace vdbmesh::detail
