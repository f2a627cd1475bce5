// Dual Marching Cubes checks its own output (see dmc_self_check.h): exact self-intersections
// (find_self_intersections: BVH and exact predicates), non-manifold edges and vertices, and
// the distance to the isosurface, on the triangles that come from merged cells.

#include "mesh/dmc_self_check.h"

#include <openvdb/tools/Interpolation.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <unordered_map>

#include "vdbmesh/analysis.h"

namespace vdbmesh::detail {

namespace {

/// Marks the triangles on edges used more than twice or twice in the same direction.
void mark_nonmanifold_edges(const Mesh& mesh, std::vector<std::uint8_t>& bad) {
    struct Use {
        std::uint64_t key;  // smaller << 32 | larger
        std::uint32_t triangle;
        bool forward;
    };
    std::vector<Use> uses;
    uses.reserve(mesh.triangles.size() * 3);
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = mesh.triangles[t][std::size_t(k)], b = mesh.triangles[t][std::size_t((k + 1) % 3)];
            uses.push_back({(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b), t, a < b});
        }
    }
    std::sort(uses.begin(), uses.end(), [](const Use& x, const Use& y) { return x.key < y.key || (x.key == y.key && x.triangle < y.triangle); });
    for (std::size_t i = 0; i < uses.size();) {
        std::size_t j = i;
        while (j < uses.size() && uses[j].key == uses[i].key) ++j;
        const bool broken = j - i > 2 || (j - i == 2 && uses[i].forward == uses[i + 1].forward);
        if (broken) {
            for (std::size_t k = i; k < j; ++k) bad[uses[k].triangle] = 1;
        }
        i = j;
    }
}

/// Marks the triangles around vertices whose triangles form more than one fan.
void mark_nonmanifold_vertices(const Mesh& mesh, std::vector<std::uint8_t>& bad) {
    const std::size_t n = mesh.vertices.size();
    std::vector<std::uint32_t> first(n + 1, 0);
    for (const auto& t : mesh.triangles) {
        for (std::uint32_t v : t) ++first[v + 1];
    }
    std::partial_sum(first.begin(), first.end(), first.begin());
    std::vector<std::uint32_t> incident(first.back());
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        for (std::uint32_t v : mesh.triangles[t]) incident[fill[v]++] = t;
    }
    std::vector<std::uint8_t> broken(n, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const auto& range) {
        std::vector<std::uint32_t> link, parent;
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            // Union-find over the link vertices: each triangle joins its two other corners.
            link.clear();
            for (std::uint32_t i = first[v]; i < first[v + 1]; ++i) {
                for (std::uint32_t w : mesh.triangles[incident[i]]) {
                    if (w != v) link.push_back(w);
                }
            }
            std::sort(link.begin(), link.end());
            link.erase(std::unique(link.begin(), link.end()), link.end());
            parent.resize(link.size());
            std::iota(parent.begin(), parent.end(), 0u);
            auto find = [&](std::uint32_t x) {
                while (parent[x] != x) x = parent[x] = parent[parent[x]];
                return x;
            };
            auto index = [&](std::uint32_t w) { return std::uint32_t(std::lower_bound(link.begin(), link.end(), w) - link.begin()); };
            std::size_t fans = link.size();
            for (std::uint32_t i = first[v]; i < first[v + 1]; ++i) {
                std::array<std::uint32_t, 2> other{};
                int k = 0;
                for (std::uint32_t w : mesh.triangles[incident[i]]) {
                    if (w != v && k < 2) other[std::size_t(k++)] = w;
                }
                if (k < 2) continue;
                const std::uint32_t a = find(index(other[0])), b = find(index(other[1]));
                if (a != b) {
                    parent[a] = b;
                    --fans;
                }
            }
            broken[v] = fans > 1;
        }
    });
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        for (std::uint32_t v : mesh.triangles[t]) {
            if (broken[v]) bad[t] = 1;
        }
    }
}

/// First-order distance (voxels) from index-space point @a p to the isosurface.
template <typename Accessor>
double isosurface_distance(Accessor& accessor, double iso, const openvdb::Vec3d& p) {
    using Sampler = openvdb::tools::BoxSampler;
    const double f = Sampler::sample(accessor, p);
    openvdb::Vec3d g;
    for (int k = 0; k < 3; ++k) {
        openvdb::Vec3d step(0.0);
        step[k] = 0.5;
        g[k] = Sampler::sample(accessor, p + step) - Sampler::sample(accessor, p - step);
    }
    const double slope = g.length();
    return slope > 0.0 ? std::abs(f - iso) / slope : 0.0;
}

void mark_off_surface(const DmcGrid& grid, const DmcContour& contour, double tolerance, std::vector<std::uint8_t>& bad) {
    const Mesh& mesh = contour.mesh;
    const openvdb::math::Transform& transform = grid.grid->transform();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangles.size()), [&](const auto& range) {
        auto accessor = grid.grid->getConstAccessor();
        for (std::size_t t = range.begin(); t != range.end(); ++t) {
            if (!contour.sources[t].merged) continue;
            // The centroid: the point of a chord farthest from the crossings it joins.
            openvdb::Vec3d centroid(0.0);
            for (int k = 0; k < 3; ++k) {
                const auto& v = mesh.vertices[mesh.triangles[t][std::size_t(k)]];
                centroid += transform.worldToIndex(openvdb::Vec3d(v[0], v[1], v[2])) / 3.0;
            }
            if (isosurface_distance(accessor, grid.iso, centroid) > tolerance) bad[t] = 1;
        }
    });
}

}  // namespace

std::vector<std::uint32_t> triangles_to_refine(const DmcGrid& grid, const DmcContour& contour, double tolerance) {
    const Mesh& mesh = contour.mesh;
    std::vector<std::uint8_t> bad(mesh.triangles.size(), 0);
    mark_nonmanifold_edges(mesh, bad);
    mark_nonmanifold_vertices(mesh, bad);
    mark_off_surface(grid, contour, tolerance, bad);
    for (const auto& [a, b] : find_self_intersections(mesh)) {
        bad[a] = 1;
        bad[b] = 1;
    }
    std::vector<std::uint32_t> result;
    for (std::uint32_t t = 0; t < bad.size(); ++t) {
        if (bad[t] && contour.sources[t].merged) result.push_back(t);
    }
    return result;
}

bool split_cells_of(const DmcGrid& grid, const DmcContour& contour, const std::vector<std::uint32_t>& triangles,
                    std::vector<LeafOctree>& octrees) {
    std::unordered_map<const FloatLeaf*, std::size_t> index_of;
    for (std::size_t i = 0; i < grid.leaves.size(); ++i) index_of.emplace(grid.leaves[i], i);
    auto accessor = grid.grid->getConstAccessor();
    bool split = false;
    for (std::uint32_t t : triangles) {
        const openvdb::Coord p = contour.sources[t].p;
        for (int c = 0; c < 8; ++c) {
            const openvdb::Coord voxel = p.offsetBy(c & 1, (c >> 1) & 1, c >> 2);
            const FloatLeaf* leaf = accessor.probeConstLeaf(voxel);
            if (!leaf) continue;
            LeafOctree& octree = octrees[index_of.at(leaf)];
            const int offset = leaf_offset(voxel.x() & 7, voxel.y() & 7, voxel.z() & 7);
            if (octree.level_at(offset) == 0) continue;
            octree.split_cell(offset);
            split = true;
        }
    }
    return split;
}

}  // namespace vdbmesh::detail
