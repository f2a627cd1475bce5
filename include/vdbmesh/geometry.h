#pragma once
/// @file geometry.h
/// @brief The geometry stage: exact self-intersection tests, the combinatorial checks of a
/// triangle mesh (edges, vertex fans, components, coincident vertices) and a bounding-volume
/// hierarchy over its triangles (OpenVDB-free). find_self_intersections() is the API; the
/// declarations in vdbmesh::detail are shared with the stages above (analysis, the
/// meshers) and may change between versions.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "vdbmesh/mesh.h"

namespace vdbmesh {

/// @brief All pairs (i < j, sorted) of non-degenerate triangles that intersect beyond what
/// they must share, decided with exact orientation predicates. Sharing is by position:
/// corners with bit-identical coordinates are the same point even under different indices.
/// - no shared corner: any common point (touching counts, as in CGAL's PMP);
/// - one shared corner: a common point other than that corner (a fold or a crossing);
/// - a shared edge: coplanar and on the same side of the edge (overlapping);
/// - all three corners shared (a duplicated face): always.
/// Degenerate triangles (repeated or collinear corners) are skipped: analyze_mesh() counts them.
/// O(n log n) with a bounding-volume hierarchy.
std::vector<std::pair<std::uint32_t, std::uint32_t>> find_self_intersections(const Mesh& mesh);

}  // namespace vdbmesh

namespace vdbmesh::detail {

using Point3 = std::array<double, 3>;

// ---- Exact tests (exact orientation predicates on the double values of the coordinates) ----

using Triangle3 = std::array<Point3, 3>;

/// True when the three points are exactly collinear (or coincide).
bool collinear(const Point3& a, const Point3& b, const Point3& c);

/// Exact sign (-1, 0, +1) of ((b - a) x (c - a)) . (d - a).
int orient3d(const Point3& a, const Point3& b, const Point3& c, const Point3& d);

/// Two non-degenerate triangles whose corners carry ids (equal ids: the same point): true when
/// they meet beyond what they share. No shared id: any common point; one: a point other than
/// that corner; two: overlapping beyond that edge; three (the same face): always. The test of
/// find_self_intersections() (ids: coincident vertices) and of the decimator's local checks.
bool triangles_intersect(const std::array<std::uint32_t, 3>& t_ids, const Triangle3& t,
                         const std::array<std::uint32_t, 3>& u_ids, const Triangle3& u);

// ---- Faces -------------------------------------------------------------------------------

enum class FaceClass : std::uint8_t {
    kRegular,         ///< three distinct, non-collinear corners
    kRepeatedVertex,  ///< an index used twice
    kZeroArea,        ///< distinct indices, exactly collinear (or coincident) corners
};

/// Throws Error when a triangle refers to a vertex that does not exist.
void check_indices(const Mesh& mesh);

/// The class of one triangle from its corners' vertices (@a ids: equal where two corners are
/// the same vertex) and their positions.
FaceClass classify_face(const std::array<std::uint32_t, 3>& ids, const Triangle3& corners);

/// One class per triangle, decided with exact predicates (parallel, deterministic).
std::vector<FaceClass> classify_faces(const Mesh& mesh);

/// Indices of the regular triangles, in increasing order.
std::vector<std::uint32_t> regular_faces(const std::vector<FaceClass>& classes);

// ---- Topology (requires valid indices: check_indices) ------------------------------------

/// The undirected edges of a mesh and the triangles using each. Self-loops (the repeated
/// corner of a repeated-vertex face) are not edges.
struct MeshEdges {
    struct Use {
        std::uint64_t key;       ///< smaller vertex << 32 | larger vertex
        std::uint32_t forward;   ///< 1 when the triangle runs smaller -> larger
        std::uint32_t triangle;
        bool operator<(const Use& o) const {
            return key != o.key ? key < o.key : (forward != o.forward ? forward < o.forward : triangle < o.triangle);
        }
    };
    std::vector<Use> uses;             ///< sorted: by edge, backward uses first, then by triangle
    std::vector<std::uint32_t> first;  ///< uses of edge e: [first[e], first[e + 1])

    std::size_t size() const { return first.empty() ? 0 : first.size() - 1; }
    std::size_t use_count(std::size_t e) const { return first[e + 1] - first[e]; }
    std::size_t forward_count(std::size_t e) const;
    bool boundary(std::size_t e) const { return use_count(e) == 1; }
    bool nonmanifold(std::size_t e) const { return use_count(e) > 2; }
    /// A direction used twice: the triangles around it are not consistently oriented.
    bool misoriented(std::size_t e) const { return forward_count(e) > 1 || use_count(e) - forward_count(e) > 1; }
    std::uint32_t vertex_a(std::size_t e) const { return std::uint32_t(uses[first[e]].key >> 32); }
    std::uint32_t vertex_b(std::size_t e) const { return std::uint32_t(uses[first[e]].key); }
};
MeshEdges mesh_edges(const Mesh& mesh);

/// Per vertex, 1 when its triangles form more than one fan (its link is not connected);
/// repeated-vertex faces are left out.
std::vector<std::uint8_t> nonmanifold_vertices(const Mesh& mesh);

/// For each vertex the smallest index of a vertex at the same position (float bits, -0 = +0).
std::vector<std::uint32_t> canonical_vertices(const Mesh& mesh);

/// What analyze_mesh() reports about the combinatorics.
struct Topology {
    std::size_t referenced_vertices = 0;
    std::size_t edges = 0;
    std::size_t boundary_edges = 0;
    std::size_t boundary_loops = 0;
    std::size_t nonmanifold_edges = 0;
    std::size_t misoriented_edges = 0;
    std::size_t nonmanifold_vertices = 0;
    std::size_t components = 0;
    /// For each triangle its component, numbered in order of first appearance.
    std::vector<std::uint32_t> component_of_triangle;
};

/// Edges (boundary loops from union-find), vertex fans and components of @a mesh.
Topology analyze_topology(const Mesh& mesh);

// ---- Bounding-volume hierarchy -----------------------------------------------------------

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

/// Spreads the low 21 bits of @a v so that two zero bits separate each: interleaving three
/// such values gives a point's Morton (Z-order) code.
std::uint64_t spread_bits(std::uint64_t v);

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
