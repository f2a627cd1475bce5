// The Decimator's corner table (process/decimator.h): linked from the triangles (which finds
// whether the mesh is closed, manifold and oriented), its components measured, changed by a
// collapse, and read back as a Mesh.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <vector>

#include "process/decimator.h"
#include "vdbmesh/union_find.h"

namespace vdbmesh::detail::decimation {

Decimator::Decimator(const Mesh& mesh, const DecimateOptions& options)
    : positions_(parallel_array<std::array<float, 3>>(mesh.vertices.size(), [&](std::size_t v) { return mesh.vertices[v]; })),
      triangles_(parallel_array<Ids>(mesh.triangles.size(), [&](std::size_t t) { return mesh.triangles[t]; })),
      alive_(parallel_array<char>(mesh.triangles.size(), [](std::size_t) { return 1; })),
      opposite_(3 * mesh.triangles.size()),  // (link_corners() writes each, or fails)
      vertex_corner_(parallel_array<std::uint32_t>(mesh.vertices.size(), [](std::size_t) { return kNone; })),
      quadrics_(parallel_array<Quadric>(mesh.vertices.size(), [](std::size_t) { return Quadric{}; })),
      cost_(3 * mesh.triangles.size()), error_(3 * mesh.triangles.size()), position_(3 * mesh.triangles.size()),  // (refresh() writes them)
      rejected_(parallel_array<char>(3 * mesh.triangles.size(), [](std::size_t) { return 0; })),
      boxes_(mesh.triangles.size()),  // (refresh() writes each)
      summaries_(parallel_array<Summary>(mesh.triangles.size(), [](std::size_t) { return Summary{}; })),
      moved_(parallel_array<char>(mesh.triangles.size(), [](std::size_t) { return 0; })), alive_count_(mesh.triangles.size()),
      target_(options.target_triangles != 0 ? options.target_triangles
                                            : std::size_t(std::ceil(options.keep_fraction * double(mesh.triangles.size())))),
      max_error_squared_(options.max_error * options.max_error), closed_manifold_(link_corners()) {}

/// Each corner's opposite: the corner of the other triangle on the edge opposite it (that
/// edge runs vertex(next c) -> vertex(prev c), and the other way in the other triangle).
/// Returns closed_manifold().
bool Decimator::link_corners() {
    const std::size_t n = positions_.size();
    const auto corners = std::uint32_t(3 * triangles_.size());
    std::vector<std::uint32_t> start(n + 1, 0);
    for (std::uint32_t c = 0; c < corners; ++c) ++start[vertex(c) + 1];
    for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> at(start[n]);  // the corners at each vertex
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t c = 0; c < corners; ++c) at[fill[vertex(c)]++] = c;
    // Round each vertex v: the edge from v to x, after its corner c, pairs with the edge from x
    // to v, before its corner d (both at v): the corners opposite them are prev(c) and next(d).
    std::atomic<bool> paired{true};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) {
                const std::uint32_t c = at[i], x = vertex(next(c));
                int found = 0;
                for (std::uint32_t j = start[v]; j < start[v + 1]; ++j) {
                    if (vertex(prev(at[j])) == x) opposite_[prev(c)] = next(at[j]), ++found;
                }
                if (found != 1) paired = false;
            }
        }
    });
    for (std::uint32_t c = 0; c < corners; ++c) vertex_corner_[vertex(c)] = c;
    if (!paired) return false;
    // Each edge paired once (so opposite_ is an involution and every walk round a vertex
    // closes): a vertex is manifold when its walk meets all its corners.
    std::atomic<bool> fans{true};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            if (start[v] == start[v + 1]) continue;
            std::uint32_t count = 0;
            around(std::uint32_t(v), [&](std::uint32_t) { ++count; });
            if (count != start[v + 1] - start[v]) fans = false;
        }
    });
    return fans;
}

/// Each vertex's component (triangles joined by shared vertices) and each component's
/// enclosed volume (six times, the sum of its triangles' determinants).
void Decimator::measure_components() {
    detail::UnionFind sets(positions_.size());
    for (const Ids& t : triangles_) sets.unite(t[0], t[1]), sets.unite(t[0], t[2]);
    std::uint32_t count = 0;
    const std::vector<std::uint32_t> component = sets.labels(count);
    volume_.assign(count, 0);
    for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
        const Ids& ids = triangles_[t];
        summaries_[t].component = component[ids[0]];
        volume_[component[ids[0]]] += dot(point(ids[0]), cross(point(ids[1]), point(ids[2])));
    }
}

/// The collapse of the edge opposite @a corner, from a (kept) to b, whose triangles are
/// t0 = (a, b, c) and t1 = (b, a, d): b's corners become a's, and the two edges left of each
/// removed triangle are joined; the corners at a go to @a dirty. The corners c and d name
/// are left to name_opposite_corners().
void Decimator::apply(std::uint32_t corner, std::vector<std::uint32_t>& dirty) {
    const std::uint32_t o = opposite_[corner];
    const std::uint32_t a = vertex(next(corner)), b = vertex(prev(corner));
    around(b, [&](std::uint32_t c) { triangles_[c / 3][c % 3] = a; });
    const std::uint32_t x0 = opposite_[next(corner)], y0 = opposite_[prev(corner)];  // across b-c and c-a
    const std::uint32_t x1 = opposite_[next(o)], y1 = opposite_[prev(o)];            // across a-d and d-b
    opposite_[x0] = y0, opposite_[y0] = x0;
    opposite_[x1] = y1, opposite_[y1] = x1;
    vertex_corner_[a] = next(y0);  // y0's triangle runs (., a, c)
    vertex_corner_[b] = kNone;
    alive_[corner / 3] = alive_[o / 3] = 0;
    moved_[corner / 3] = moved_[o / 3] = 1;  // (off the settled grid from now on)
    positions_[a] = position_[corner];
    quadrics_[a] = quadrics_[a] + quadrics_[b];
    around(a, [&](std::uint32_t c) { dirty.push_back(c); });
}

/// After apply(@a corner): a corner at c and at d off the removed triangles (whose
/// opposite_ entries still name the corners across their edges).
void Decimator::name_opposite_corners(std::uint32_t corner) {
    const std::uint32_t o = opposite_[corner];
    vertex_corner_[vertex(corner)] = next(opposite_[next(corner)]);
    vertex_corner_[vertex(o)] = next(opposite_[next(o)]);
}

Mesh Decimator::compact() const {
    Mesh mesh;
    std::vector<std::uint32_t> index(positions_.size(), kNone);
    for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
        if (!alive_[t]) continue;
        Ids ids = triangles_[t];
        for (std::uint32_t& v : ids) {
            if (index[v] == kNone) index[v] = std::uint32_t(mesh.vertices.size()), mesh.vertices.push_back(positions_[v]);
            v = index[v];
        }
        mesh.triangles.push_back(ids);
    }
    return mesh;
}

}  // namespace vdbmesh::detail::decimation
