// StreamTopology: the counts of topology.cpp from sorted records instead of a mesh in memory
// (the same definitions, so the same figures): see stream_topology.h.
#include "analysis/stream_topology.h"

#include <algorithm>
#include <vector>

#include "vdbmesh/union_find.h"

namespace vdbmesh::detail {

StreamTopology::StreamTopology(std::size_t run_records) : edges_(run_records), corners_(run_records) {}

void StreamTopology::add(const std::array<std::uint32_t, 3>& t) {
    const bool repeated = t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
    if (t[0] == t[1] && t[1] == t[2]) edges_.add({t[0], t[0], 0, 0});
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = t[k], b = t[(k + 1) % 3];
        if (a != b) edges_.add({std::min(a, b), std::max(a, b), std::uint16_t(a < b), std::uint16_t(a > b)});
        if (!repeated) corners_.add({a, b, t[(k + 2) % 3]});
    }
}

void StreamTopology::CombineEdgeUses::operator()(std::vector<EdgeUse>& run) const {
    const auto saturated = [](std::uint32_t count) { return std::uint16_t(std::min<std::uint32_t>(count, kMostUses)); };
    std::size_t kept = 0;
    for (std::size_t i = 0; i < run.size(); ++i) {
        if (kept > 0 && run[i].a == run[kept - 1].a && run[i].b == run[kept - 1].b) {
            EdgeUse& last = run[kept - 1];
            last.forward = saturated(std::uint32_t(last.forward) + run[i].forward);
            last.backward = saturated(std::uint32_t(last.backward) + run[i].backward);
        } else {
            run[kept++] = run[i];
        }
    }
    run.resize(kept);
}

void StreamTopology::count_edges(std::size_t vertices, Topology& topology, const std::function<void()>& step) {
    UnionFind components(vertices), boundary(vertices);
    std::vector<bool> used(vertices, false), on_boundary(vertices, false);
    EdgeUse edge{0, 0, 0, 0};
    std::size_t forward = 0, backward = 0;  // the uses of `edge` so far
    const auto close_edge = [&] {
        const std::size_t uses = forward + backward;
        if (uses == 0) return;
        ++topology.edges;
        if (uses > 2) ++topology.nonmanifold_edges;
        if (forward > 1 || backward > 1) ++topology.misoriented_edges;
        if (uses == 1) {
            ++topology.boundary_edges;
            boundary.unite(edge.a, edge.b);
            on_boundary[edge.a] = on_boundary[edge.b] = true;
        }
        components.unite(edge.a, edge.b);
    };
    edges_.merge([&](const EdgeUse& use) {
        step();
        used[use.a] = used[use.b] = true;
        if (use.a == use.b) return;
        if (use.a == edge.a && use.b == edge.b) {
            forward += use.forward, backward += use.backward;
            return;
        }
        close_edge();
        edge = use, forward = use.forward, backward = use.backward;
    });
    close_edge();
    for (std::uint32_t v = 0; v < vertices; ++v) {
        topology.referenced_vertices += used[v];
        topology.components += used[v] && components.find(v) == v;
        topology.boundary_loops += on_boundary[v] && boundary.find(v) == v;
    }
    if (keep_components_) {
        components_.resize(vertices);
        for (std::uint32_t v = 0; v < vertices; ++v) components_[v] = components.find(v);
    }
}

void StreamTopology::count_fans(Topology& topology, const std::function<void()>& step) {
    std::vector<CornerUse> around;  // the corners of one vertex
    std::vector<std::uint32_t> link;
    UnionFind sets;
    const auto close_vertex = [&] {
        if (around.empty()) return;
        link.clear();
        for (const CornerUse& c : around) link.push_back(c.next), link.push_back(c.previous);
        std::sort(link.begin(), link.end());
        link.erase(std::unique(link.begin(), link.end()), link.end());
        sets.reset(link.size());
        const auto local = [&](std::uint32_t w) { return std::uint32_t(std::lower_bound(link.begin(), link.end(), w) - link.begin()); };
        std::size_t fans = link.size();
        for (const CornerUse& c : around) fans -= sets.unite(local(c.next), local(c.previous));
        topology.nonmanifold_vertices += fans > 1;
        around.clear();
    };
    corners_.merge([&](const CornerUse& corner) {
        step();
        if (!around.empty() && around.front().vertex != corner.vertex) close_vertex();
        around.push_back(corner);
    });
    close_vertex();
}

Topology StreamTopology::finish(std::size_t vertices, const std::function<void(double)>& progress) {
    const double records = double(edges_.size() + corners_.size());
    std::uint64_t merged = 0;
    const std::function<void()> step = [&] {
        if (++merged % (std::uint64_t(1) << 20) == 0 && progress) progress(double(merged) / records);
    };
    Topology topology;
    count_edges(vertices, topology, step);
    count_fans(topology, step);
    return topology;
}

}  // namespace vdbmesh::detail
