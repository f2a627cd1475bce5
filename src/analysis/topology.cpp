// Combinatorial validation of an indexed triangle mesh (the checks listed in DESIGN.md
// section 6): each undirected edge's uses are counted from a sorted list of directed edges
// (1: boundary, > 2: non-manifold, a direction used twice: misoriented); a vertex is manifold
// when the triangles around it form one fan (its link is connected); components, boundary
// loops and the vertex fans come from union-find.
#include "analysis/topology.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <numeric>

namespace vdbmesh::detail {
namespace {

/// Union-find with path halving; the smaller index becomes the root (deterministic).
class DisjointSets {
public:
    explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
    std::uint32_t find(std::uint32_t v) {
        while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
        return v;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a), b = find(b);
        if (a != b) parent_[std::max(a, b)] = std::min(a, b);
    }

private:
    std::vector<std::uint32_t> parent_;
};

struct DirectedEdge {
    std::uint64_t key;      ///< min << 32 | max
    std::uint32_t forward;  ///< 1 when the triangle runs min -> max
    bool operator<(const DirectedEdge& o) const { return key < o.key || (key == o.key && forward < o.forward); }
};

std::vector<DirectedEdge> directed_edges(const Mesh& mesh) {
    std::vector<DirectedEdge> edges;
    edges.reserve(3 * mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            if (a == b) continue;
            edges.push_back({std::uint64_t(std::min(a, b)) << 32 | std::max(a, b), a < b ? 1u : 0u});
        }
    }
    tbb::parallel_sort(edges.begin(), edges.end());
    return edges;
}

void count_edges(const Mesh& mesh, Topology& topology) {
    const std::vector<DirectedEdge> edges = directed_edges(mesh);
    DisjointSets boundary(mesh.vertices.size());
    std::vector<char> on_boundary(mesh.vertices.size(), 0);
    for (std::size_t begin = 0; begin < edges.size();) {
        std::size_t end = begin, forward = 0;
        for (; end < edges.size() && edges[end].key == edges[begin].key; ++end) forward += edges[end].forward;
        const std::size_t uses = end - begin, backward = uses - forward;
        ++topology.edges;
        if (uses > 2) ++topology.nonmanifold_edges;
        if (forward > 1 || backward > 1) ++topology.misoriented_edges;
        if (uses == 1) {
            ++topology.boundary_edges;
            const auto a = std::uint32_t(edges[begin].key >> 32), b = std::uint32_t(edges[begin].key);
            boundary.unite(a, b);
            on_boundary[a] = on_boundary[b] = 1;
        }
        begin = end;
    }
    for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
        if (on_boundary[v] && boundary.find(v) == v) ++topology.boundary_loops;
    }
}

/// Compressed lists of the triangles around each vertex (repeated-vertex faces left out).
struct VertexTriangles {
    std::vector<std::uint32_t> offsets, triangles;
};

bool has_repeated_vertex(const std::array<std::uint32_t, 3>& t) { return t[0] == t[1] || t[1] == t[2] || t[2] == t[0]; }

VertexTriangles vertex_triangles(const Mesh& mesh) {
    VertexTriangles result;
    result.offsets.assign(mesh.vertices.size() + 1, 0);
    for (const auto& t : mesh.triangles) {
        if (has_repeated_vertex(t)) continue;
        for (const std::uint32_t v : t) ++result.offsets[v + 1];
    }
    std::partial_sum(result.offsets.begin(), result.offsets.end(), result.offsets.begin());
    result.triangles.resize(result.offsets.back());
    std::vector<std::uint32_t> fill(result.offsets.begin(), result.offsets.end() - 1);
    for (std::uint32_t i = 0; i < mesh.triangles.size(); ++i) {
        if (has_repeated_vertex(mesh.triangles[i])) continue;
        for (const std::uint32_t v : mesh.triangles[i]) result.triangles[fill[v]++] = i;
    }
    return result;
}

/// Number of fans around @a v: components of its link (the opposite edges of its triangles).
std::size_t count_fans(const Mesh& mesh, const VertexTriangles& around, std::uint32_t v,
                       std::vector<std::uint32_t>& link, std::vector<std::uint32_t>& parent) {
    link.clear();
    for (std::uint32_t k = around.offsets[v]; k < around.offsets[v + 1]; ++k) {
        for (const std::uint32_t w : mesh.triangles[around.triangles[k]]) {
            if (w != v) link.push_back(w);
        }
    }
    std::sort(link.begin(), link.end());
    link.erase(std::unique(link.begin(), link.end()), link.end());
    parent.resize(link.size());
    std::iota(parent.begin(), parent.end(), 0u);
    const auto local = [&](std::uint32_t w) { return std::uint32_t(std::lower_bound(link.begin(), link.end(), w) - link.begin()); };
    const auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::size_t fans = link.size();
    for (std::uint32_t k = around.offsets[v]; k < around.offsets[v + 1]; ++k) {
        const auto& t = mesh.triangles[around.triangles[k]];
        const int corner = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        const std::uint32_t a = find(local(t[(corner + 1) % 3])), b = find(local(t[(corner + 2) % 3]));
        if (a != b) parent[std::max(a, b)] = std::min(a, b), --fans;
    }
    return fans;
}

void count_vertex_fans(const Mesh& mesh, Topology& topology) {
    const VertexTriangles around = vertex_triangles(mesh);
    topology.nonmanifold_vertices = tbb::parallel_reduce(
        tbb::blocked_range<std::uint32_t>(0, std::uint32_t(mesh.vertices.size()), 4096), std::size_t{0},
        [&](const tbb::blocked_range<std::uint32_t>& range, std::size_t count) {
            std::vector<std::uint32_t> link, parent;
            for (std::uint32_t v = range.begin(); v != range.end(); ++v) {
                if (count_fans(mesh, around, v, link, parent) > 1) ++count;
            }
            return count;
        },
        std::plus<>());
}

void label_components(const Mesh& mesh, Topology& topology) {
    DisjointSets sets(mesh.vertices.size());
    std::vector<char> referenced(mesh.vertices.size(), 0);
    for (const auto& t : mesh.triangles) {
        sets.unite(t[0], t[1]);
        sets.unite(t[1], t[2]);
        referenced[t[0]] = referenced[t[1]] = referenced[t[2]] = 1;
    }
    topology.referenced_vertices = std::size_t(std::count(referenced.begin(), referenced.end(), 1));
    constexpr std::uint32_t kUnlabelled = ~0u;
    std::vector<std::uint32_t> label(mesh.vertices.size(), kUnlabelled);
    topology.component_of_triangle.resize(mesh.triangles.size());
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        std::uint32_t& root_label = label[sets.find(mesh.triangles[i][0])];
        if (root_label == kUnlabelled) root_label = std::uint32_t(topology.components++);
        topology.component_of_triangle[i] = root_label;
    }
}

}  // namespace

Topology analyze_topology(const Mesh& mesh) {
    Topology topology;
    count_edges(mesh, topology);
    count_vertex_fans(mesh, topology);
    label_components(mesh, topology);
    return topology;
}

}  // namespace vdbmesh::detail
