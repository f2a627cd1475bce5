#pragma once
// Private: the topology of a mesh that is never held, for the bounded check (issue 28). Each
// triangle becomes records in two external sorts: its edges as (smaller vertex, larger vertex,
// direction), which counted per edge give boundary, non-manifold and misoriented edges, and
// with two union-finds over the vertices the components and the boundary loops; and its
// corners as (vertex, next, previous), which grouped per vertex give the fans around it, as
// topology.cpp counts them for a mesh in memory.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "analysis/external_sort.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh::detail {

/// Bytes per vertex while the topology is counted (two union-finds, two flags).
constexpr double kTopologyBytesPerVertex = 8.25;

class StreamTopology {
public:
    /// Each sort gathers runs of @a run_records records.
    explicit StreamTopology(std::size_t run_records);
    void add(const std::array<std::uint32_t, 3>& triangle);
    /// The counts for a mesh of @a vertices vertices (every index below it); @a progress (if
    /// set) hears the share of the records merged.
    Topology finish(std::size_t vertices, const std::function<void(double)>& progress);
    /// Sorted runs written to temporary files so far.
    std::size_t runs() const { return edges_.runs() + corners_.runs(); }
    /// Asks finish() to keep each vertex's component, for take_components() (the bounded
    /// measure's per-component sums): kComponentBytesPerVertex more while the edges are counted.
    void keep_components() { keep_components_ = true; }
    /// After finish() with keep_components(): each vertex's component named by its smallest
    /// vertex (the union-find's root); unused vertices name themselves.
    std::vector<std::uint32_t> take_components() { return std::move(components_); }
    static constexpr double kComponentBytesPerVertex = 4;

    /// Uses of the edge between vertices a < b: how many run a -> b and b -> a. Added one use
    /// at a time, counted together in each sorted run (CombineEdgeUses) up to kMostUses, as
    /// the verdicts need no more (1: boundary, 2, more: non-manifold). A triangle on one vertex
    /// alone leaves (v, v, 0, 0), which only marks v as used.
    struct EdgeUse {
        std::uint32_t a, b;
        std::uint16_t forward, backward;
        bool operator<(const EdgeUse& o) const {
            return a != o.a ? a < o.a : (b != o.b ? b < o.b : (forward != o.forward ? forward < o.forward : backward < o.backward));
        }
    };
    static constexpr std::uint16_t kMostUses = 0xffff;
    /// Each edge of a sorted run once, with its uses added.
    struct CombineEdgeUses {
        void operator()(std::vector<EdgeUse>& run) const;
    };
    /// A corner of a triangle without a repeated vertex: the vertex and its two neighbours.
    struct CornerUse {
        std::uint32_t vertex, next, previous;
        bool operator<(const CornerUse& o) const {
            return vertex != o.vertex ? vertex < o.vertex : (next != o.next ? next < o.next : previous < o.previous);
        }
    };

private:
    void count_edges(std::size_t vertices, Topology& topology, const std::function<void()>& step);
    void count_fans(Topology& topology, const std::function<void()>& step);

    ExternalSorter<EdgeUse, CombineEdgeUses> edges_;
    ExternalSorter<CornerUse> corners_;
    bool keep_components_ = false;
    std::vector<std::uint32_t> components_;
};

}  // namespace vdbmesh::detail
