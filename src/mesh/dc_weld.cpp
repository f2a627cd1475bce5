// The weld of intersection-free octree contouring: keyed vertices and triangles, node after
// node in z-major order (docs/dmc.md, "Bricks"), into one indexed mesh. Every list has a fixed
// order, so the mesh does not depend on the thread count or on how the nodes were bricked.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "mesh/dual_contouring.h"
#include "mesh/dc_key_index.h"
#include "vdbmesh/error.h"
#include "vdbmesh/huge_pages.h"

namespace vdbmesh::detail {

namespace {

/// The vertex and triangle lists of the nodes in output order: per node its blocks' vertices
/// then its coarse cells; its blocks' triangles.
struct Lists {
    std::vector<std::vector<IfcVertex>*> vertices;
    std::vector<std::vector<std::array<std::uint64_t, 3>>*> triangles;
};

Lists lists_in_order(std::vector<IfcNodeOutput>& nodes) {
    Lists lists;
    for (IfcNodeOutput& node : nodes) {
        for (IfcBlockOutput& block : node.blocks) lists.vertices.push_back(&block.vertices);
        lists.vertices.push_back(&node.coarse);
        for (IfcBlockOutput& block : node.blocks) lists.triangles.push_back(&block.triangles);
    }
    return lists;
}

/// Exclusive prefix sums of the lists' sizes (one more entry: the total).
template <typename List>
std::vector<std::size_t> first_of(const std::vector<List*>& lists) {
    std::vector<std::size_t> first(lists.size() + 1, 0);
    for (std::size_t i = 0; i < lists.size(); ++i) first[i + 1] = first[i] + lists[i]->size();
    return first;
}

/// The vertices' keys and positions apart (the positions become the mesh's), each list
/// released once copied.
struct GatheredVertices {
    std::vector<std::uint64_t> keys;
    std::vector<std::array<float, 3>> positions;
};

GatheredVertices gather_vertices(const std::vector<std::vector<IfcVertex>*>& lists) {
    const std::vector<std::size_t> first = first_of(lists);
    GatheredVertices gathered;
    reserve_on_huge_pages(gathered.keys, first.back());
    gathered.keys.resize(first.back());
    reserve_on_huge_pages(gathered.positions, first.back());
    gathered.positions.resize(first.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lists.size()), [&](const auto& range) {
        for (std::size_t l = range.begin(); l != range.end(); ++l) {
            std::size_t next = first[l];
            for (const IfcVertex& v : *lists[l]) {
                gathered.keys[next] = v.key;
                gathered.positions[next++] = v.position;
            }
            *lists[l] = {};
        }
    });
    return gathered;
}

}  // namespace

Mesh weld_ifc_nodes(std::vector<IfcNodeOutput>&& nodes) {
    const Lists lists = lists_in_order(nodes);
    const std::vector<std::size_t> first_triangle = first_of(lists.triangles);
    GatheredVertices vertices = gather_vertices(lists.vertices);
    const std::size_t vertex_count = vertices.keys.size();
    if (vertex_count >= IfcKeyIndex::kMissing) throw Error("contouring: more than 2^32 vertices");
    const IfcKeyIndex index_of(vertices.keys);
    vertices.keys = {};
    Mesh mesh;
    reserve_on_huge_pages(mesh.triangles, first_triangle.back());
    mesh.triangles.resize(first_triangle.back());
    std::vector<std::uint8_t> used;
    reserve_on_huge_pages(used, vertex_count);
    used.resize(vertex_count, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lists.triangles.size()), [&](const auto& range) {
        for (std::size_t l = range.begin(); l != range.end(); ++l) {
            auto& keyed = *lists.triangles[l];
            constexpr std::size_t kAhead = 8;  // triangles: about the latency of a miss
            for (std::size_t t = 0; t < std::min(kAhead, keyed.size()); ++t) {
                for (const std::uint64_t key : keyed[t]) index_of.prefetch(key);
            }
            for (std::size_t t = 0; t < keyed.size(); ++t) {
                if (t + kAhead < keyed.size()) {
                    for (const std::uint64_t key : keyed[t + kAhead]) index_of.prefetch(key);
                }
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t index = index_of.find(keyed[t][k]);
                    if (index == IfcKeyIndex::kMissing) throw Error("contouring: a triangle refers to a missing vertex");
                    mesh.triangles[first_triangle[l] + t][k] = index;
                    used[index] = 1;  // every writer writes 1: no race on the value
                }
            }
            keyed = {};
        }
    });
    const std::size_t used_count = std::size_t(std::count(used.begin(), used.end(), std::uint8_t(1)));
    if (used_count == vertex_count) {  // as on every scan measured: no renumbering
        mesh.vertices = std::move(vertices.positions);
        return mesh;
    }
    reserve_on_huge_pages(mesh.vertices, used_count);
    std::vector<std::uint32_t> new_index;
    reserve_on_huge_pages(new_index, vertex_count);
    new_index.resize(vertex_count);
    for (std::size_t v = 0; v < vertex_count; ++v) {
        new_index[v] = std::uint32_t(mesh.vertices.size());
        if (used[v]) mesh.vertices.push_back(vertices.positions[v]);
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangles.size()), [&](const auto& range) {
        for (std::size_t t = range.begin(); t != range.end(); ++t) {
            for (auto& v : mesh.triangles[t]) v = new_index[v];
        }
    });
    return mesh;
}

}  // namespace vdbmesh::detail
