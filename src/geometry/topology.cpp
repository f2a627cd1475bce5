// Combinatorial validation of an indexed triangle mesh (the checks listed in DESIGN.md
// section 6): each undirected edge's uses are counted from a sorted list of directed edges
// (1: boundary, > 2: non-manifold, a direction used twice: misoriented); a vertex is manifold
// when the triangles around it form one fan (its link is connected); components, boundary
// loops and the vertex fans come from union-find; coincident vertices from a sort of the
// coordinates' bits. analyze_mesh() counts them.
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <tuple>

#include "vdbmesh/geometry.h"
#include "vdbmesh/union_find.h"

namespace vdbmesh::detail {
namespace {

void count_edges(const Mesh& mesh, Topology& topology) {
    const MeshEdges edges = mesh_edges(mesh);
    UnionFind boundary(mesh.vertices.size());
    std::vector<char> on_boundary(mesh.vertices.size(), 0);
    topology.edges = edges.size();
    for (std::size_t e = 0; e < edges.size(); ++e) {
        if (edges.nonmanifold(e)) ++topology.nonmanifold_edges;
        if (edges.misoriented(e)) ++topology.misoriented_edges;
        if (edges.boundary(e)) {
            ++topology.boundary_edges;
            const std::uint32_t a = edges.vertex_a(e), b = edges.vertex_b(e);
            boundary.unite(a, b);
            on_boundary[a] = on_boundary[b] = 1;
        }
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
std::size_t count_fans(const Mesh& mesh, const VertexTriangles& around, std::uint32_t v, std::vector<std::uint32_t>& link,
                       UnionFind& sets) {
    link.clear();
    for (std::uint32_t k = around.offsets[v]; k < around.offsets[v + 1]; ++k) {
        for (const std::uint32_t w : mesh.triangles[around.triangles[k]]) {
            if (w != v) link.push_back(w);
        }
    }
    std::sort(link.begin(), link.end());
    link.erase(std::unique(link.begin(), link.end()), link.end());
    sets.reset(link.size());
    const auto local = [&](std::uint32_t w) { return std::uint32_t(std::lower_bound(link.begin(), link.end(), w) - link.begin()); };
    std::size_t fans = link.size();
    for (std::uint32_t k = around.offsets[v]; k < around.offsets[v + 1]; ++k) {
        const auto& t = mesh.triangles[around.triangles[k]];
        const int corner = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        fans -= sets.unite(local(t[(corner + 1) % 3]), local(t[(corner + 2) % 3]));
    }
    return fans;
}

void label_components(const Mesh& mesh, Topology& topology) {
    UnionFind sets(mesh.vertices.size());
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

std::size_t MeshEdges::forward_count(std::size_t e) const {
    std::size_t forward = 0;
    for (std::uint32_t i = first[e]; i < first[e + 1]; ++i) forward += uses[i].forward;
    return forward;
}

MeshEdges mesh_edges(const Mesh& mesh) {
    MeshEdges edges;
    edges.uses.reserve(3 * mesh.triangles.size());
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
            if (a == b) continue;
            edges.uses.push_back({std::uint64_t(std::min(a, b)) << 32 | std::max(a, b), a < b ? 1u : 0u, t});
        }
    }
    tbb::parallel_sort(edges.uses.begin(), edges.uses.end());
    for (std::uint32_t i = 0; i < edges.uses.size(); ++i) {
        if (i == 0 || edges.uses[i].key != edges.uses[i - 1].key) edges.first.push_back(i);
    }
    edges.first.push_back(std::uint32_t(edges.uses.size()));
    return edges;
}

std::vector<std::uint8_t> nonmanifold_vertices(const Mesh& mesh) {
    const VertexTriangles around = vertex_triangles(mesh);
    std::vector<std::uint8_t> broken(mesh.vertices.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(mesh.vertices.size()), 4096),
                      [&](const tbb::blocked_range<std::uint32_t>& range) {
                          std::vector<std::uint32_t> link;
                          UnionFind sets;
                          for (std::uint32_t v = range.begin(); v != range.end(); ++v) {
                              broken[v] = count_fans(mesh, around, v, link, sets) > 1;
                          }
                      });
    return broken;
}

std::vector<std::uint32_t> canonical_vertices(const Mesh& mesh) {
    struct Key {
        std::uint32_t x, y, z, index;
        bool operator<(const Key& o) const { return std::tie(x, y, z, index) < std::tie(o.x, o.y, o.z, o.index); }
    };
    const std::size_t n = mesh.vertices.size();
    std::vector<Key> keys(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
        std::uint32_t bits[3];
        for (int k = 0; k < 3; ++k) {
            const float value = mesh.vertices[i][k] + 0.0f;  // -0 becomes +0
            std::memcpy(&bits[k], &value, sizeof value);
        }
        keys[i] = {bits[0], bits[1], bits[2], std::uint32_t(i)};
    });
    tbb::parallel_sort(keys.begin(), keys.end());
    std::vector<std::uint32_t> canonical(n);
    for (std::size_t i = 0; i < n; ++i) {
        const bool same_as_previous =
            i > 0 && keys[i].x == keys[i - 1].x && keys[i].y == keys[i - 1].y && keys[i].z == keys[i - 1].z;
        canonical[keys[i].index] = same_as_previous ? canonical[keys[i - 1].index] : keys[i].index;
    }
    return canonical;
}

Topology analyze_topology(const Mesh& mesh) {
    Topology topology;
    count_edges(mesh, topology);
    const std::vector<std::uint8_t> broken = nonmanifold_vertices(mesh);
    topology.nonmanifold_vertices = std::size_t(std::count(broken.begin(), broken.end(), 1));
    label_components(mesh, topology);
    return topology;
}

}  // namespace vdbmesh::detail
