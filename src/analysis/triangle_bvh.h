#pragma once
// Private: a bounding-volume hierarchy over a mesh's triangles, for overlap and
// closest-point queries.

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
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

    /// The closest point of the listed triangles to @a p; requires at least one triangle. Only
    /// triangles nearer than sqrt(@a bound_squared) are looked at: where none is, the result
    /// keeps that bound as its distance.
    ClosestPoint closest_point(const Point3& p, double bound_squared = std::numeric_limits<double>::infinity()) const;

    /// The closest point of triangle @a triangle of the mesh to @a p.
    ClosestPoint closest_on_triangle(const Point3& p, std::uint32_t triangle) const;

    bool empty() const { return nodes_.empty(); }
    /// Self-overlap, one leaf at a time (for parallel loops over leaf_count()): calls
    /// visit(first, second) for every pair of listed triangles whose boxes overlap, where the
    /// first lies in leaf @a leaf and comes before the second in tree order. Over all leaves
    /// every overlapping pair is visited exactly once.
    template <class Visit>
    void visit_overlapping_pairs(std::size_t leaf, Visit&& visit) const;
    std::size_t leaf_count() const { return leaves_.size(); }

private:
    struct Node {
        Box box;
        std::uint32_t begin = 0, end = 0;  ///< the positions in order_ below this node
        std::uint32_t right = 0;           ///< inner: index of the right child (the left follows); leaf: 0
    };
    static constexpr int kLeafSize = 4;
    // 63 levels of Morton bits, then halving at most 2^32 equal codes.
    static constexpr int kMaxDepth = 100;

    std::uint32_t build(std::uint32_t begin, std::uint32_t end, const std::vector<std::uint64_t>& codes);

    const Mesh* mesh_;
    std::vector<std::uint32_t> leaves_;  ///< node indices of the leaves, in position order
    std::vector<std::uint32_t> order_;  ///< triangles in Morton order
    std::vector<Box> boxes_;            ///< their boxes, in the same order
    std::vector<Node> nodes_;
};

template <class Visit>
void TriangleBvh::visit_overlapping_pairs(std::size_t leaf, Visit&& visit) const {
    const Node& query = nodes_[leaves_[leaf]];
    std::uint32_t stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const std::uint32_t index = stack[--top];
        const Node& node = nodes_[index];
        // Nodes wholly before the query leaf pair with it from their own leaves.
        if (node.end <= query.begin || !boxes_overlap(node.box, query.box)) continue;
        if (node.right != 0) {
            stack[top++] = node.right;
            stack[top++] = index + 1;
            continue;
        }
        for (std::uint32_t p = query.begin; p < query.end; ++p) {
            for (std::uint32_t q = std::max(node.begin, p + 1); q < node.end; ++q) {
                if (boxes_overlap(boxes_[p], boxes_[q])) visit(order_[p], order_[q]);
            }
        }
    }
}

}  // namespace vdbmesh::detail
