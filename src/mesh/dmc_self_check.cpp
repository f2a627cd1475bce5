// Dual Marching Cubes checks its own output (see dmc_self_check.h): exact self-intersections
// (find_self_intersections: BVH and exact predicates), non-manifold edges and vertices (the
// checks of analyze_mesh(), geometry.h), coincident vertices, and the distance to the
// isosurface, on the triangles that come from merged cells.

#include "mesh/dmc_self_check.h"

#include <openvdb/tools/Interpolation.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "mesh/dmc_tangent.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/trilinear_field.h"

namespace vdbmesh::detail {

namespace {

/// Marks the triangles on edges used more than twice or twice in the same direction.
void mark_nonmanifold_edges(const Mesh& mesh, std::vector<std::uint8_t>& bad) {
    const MeshEdges edges = mesh_edges(mesh);
    for (std::size_t e = 0; e < edges.size(); ++e) {
        if (!edges.nonmanifold(e) && !edges.misoriented(e)) continue;
        for (std::uint32_t i = edges.first[e]; i < edges.first[e + 1]; ++i) bad[edges.uses[i].triangle] = 1;
    }
}

/// Marks the triangles around vertices whose triangles form more than one fan; only the
/// vertices flagged in @a judged count when it is not empty.
void mark_nonmanifold_vertices(const Mesh& mesh, const std::vector<std::uint8_t>& judged, std::vector<std::uint8_t>& bad) {
    const std::vector<std::uint8_t> broken = nonmanifold_vertices(mesh);
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        for (std::uint32_t v : mesh.triangles[t]) {
            if (broken[v] && (judged.empty() || judged[v])) bad[t] = 1;
        }
    }
}

/// Marks the triangles on distinct vertices that share a position (float bits, -0 = +0):
/// written out and welded, they would be degenerate or non-manifold.
void mark_coincident_vertices(const Mesh& mesh, std::vector<std::uint8_t>& bad) {
    const std::vector<std::uint32_t> canonical = canonical_vertices(mesh);
    std::vector<std::uint8_t> shared(mesh.vertices.size(), 0);
    for (std::uint32_t v = 0; v < canonical.size(); ++v) {
        if (canonical[v] != v) shared[v] = shared[canonical[v]] = 1;
    }
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        for (std::uint32_t v : mesh.triangles[t]) {
            if (shared[v]) bad[t] = 1;
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

/// Whether @a p (index space) lies within @a tolerance voxels of the isosurface, tried from
/// the cheapest test up: the first-order distance |f - iso| / |grad f|; Newton's projection
/// onto the surface; the nearest of the samples' exact tangent planes (the trilinear field
/// rounds sharp edges and corners the QEF vertices keep); the closest-point search of
/// isosurface_search.cpp. On noisy scans the first-order distance reads far too long where
/// the gradient is weak (two thirds of the bunny CT's flagged centroids lay within the
/// tolerance of the Marching Cubes surface), and every split cell costs triangles. Newton's
/// and the search's points are on the surface, so they never accept a point farther away.
template <typename Accessor>
bool near_isosurface(Accessor& accessor, const TrilinearField& field, double iso, const openvdb::Vec3d& p, double tolerance) {
    if (isosurface_distance(accessor, iso, p) <= tolerance) return true;
    const auto within = [&](const std::optional<openvdb::Vec3d>& q) { return q && (*q - p).length() <= tolerance; };
    if (within(project_onto_isosurface(field, iso, p))) return true;
    if (tangent_plane_distance(accessor, iso, p) <= tolerance) return true;
    return within(closest_isosurface_point(field, iso, p));
}

/// Marks the listed triangles from merged cells whose centroid strays from the isosurface.
void mark_off_surface(const DmcGrid& grid, const DmcContour& contour, double tolerance,
                      const std::vector<std::uint32_t>& triangles, std::vector<std::uint8_t>& bad) {
    const Mesh& mesh = contour.mesh;
    const openvdb::math::Transform& transform = grid.grid->transform();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size()), [&](const auto& range) {
        auto accessor = grid.grid->getConstAccessor();
        const TrilinearField field(*grid.grid);
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const std::uint32_t t = triangles[i];
            if (!contour.sources[t].merged) continue;
            // The centroid: the point of a chord farthest from the crossings it joins.
            openvdb::Vec3d centroid(0.0);
            for (int k = 0; k < 3; ++k) {
                const auto& v = mesh.vertices[mesh.triangles[t][std::size_t(k)]];
                centroid += transform.worldToIndex(openvdb::Vec3d(v[0], v[1], v[2])) / 3.0;
            }
            if (!near_isosurface(accessor, field, grid.iso, centroid, tolerance)) bad[t] = 1;
        }
    });
}

/// Key of the cube (x, y, z) (21 bits per axis; far cubes alias, which only adds triangles).
std::uint64_t cube_key(std::int64_t x, std::int64_t y, std::int64_t z) {
    constexpr std::int64_t kMask = (std::int64_t(1) << 21) - 1;
    return (std::uint64_t(x & kMask) << 42) | (std::uint64_t(y & kMask) << 21) | std::uint64_t(z & kMask);
}

/// The range of cubes of edge @a cube that triangle @a t's box touches.
void cube_range(const Mesh& mesh, std::uint32_t t, double cube, std::array<std::int64_t, 3>& lo, std::array<std::int64_t, 3>& hi) {
    for (int k = 0; k < 3; ++k) {
        float a = mesh.vertices[mesh.triangles[t][0]][k], b = a;
        for (int c = 1; c < 3; ++c) {
            a = std::min(a, mesh.vertices[mesh.triangles[t][std::size_t(c)]][k]);
            b = std::max(b, mesh.vertices[mesh.triangles[t][std::size_t(c)]][k]);
        }
        lo[std::size_t(k)] = std::int64_t(std::floor(double(a) / cube));
        hi[std::size_t(k)] = std::int64_t(std::floor(double(b) / cube));
    }
}

/// Per triangle: whether a corner of its dual cell lies in a cell split since the last check.
std::vector<std::uint8_t> changed_triangles(const DmcGrid& grid, const DmcContour& contour, const SplitVoxels& split) {
    std::vector<std::uint8_t> changed(contour.mesh.triangles.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid.leaves.size()), [&](const auto& range) {
        for (std::size_t leaf = range.begin(); leaf != range.end(); ++leaf) {
            if (!grid.any_neighbour(leaf, [&](std::size_t n) { return split.changed[n]; })) continue;
            const openvdb::Coord origin = grid.leaves[leaf]->origin();
            for (std::size_t t = contour.first_triangle[leaf]; t < contour.first_triangle[leaf + 1]; ++t) {
                const openvdb::Coord p = contour.sources[t].p - origin;
                for (int c = 0; c < 8 && !changed[t]; ++c) {
                    const int x = p.x() + (c & 1), y = p.y() + ((c >> 1) & 1), z = p.z() + (c >> 2);
                    const std::int32_t holder = grid.leaf_at(leaf, x, y, z);
                    changed[t] = holder >= 0 && split.voxels[std::size_t(holder)][std::size_t(leaf_offset(x & 7, y & 7, z & 7))];
                }
            }
        }
    });
    return changed;
}

/// Sorted keys of the cubes of edge @a cube (world units) that the boxes of the flagged
/// triangles touch.
std::vector<std::uint64_t> touched_cubes(const Mesh& mesh, const std::vector<std::uint8_t>& flagged, double cube) {
    std::vector<std::uint64_t> keys;
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        if (!flagged[t]) continue;
        std::array<std::int64_t, 3> lo{}, hi{};
        cube_range(mesh, t, cube, lo, hi);
        for (std::int64_t x = lo[0]; x <= hi[0]; ++x) {
            for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
                for (std::int64_t z = lo[2]; z <= hi[2]; ++z) keys.push_back(cube_key(x, y, z));
            }
        }
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return keys;
}

/// The triangles that can be bad together with a changed one: the changed ones, those
/// sharing a vertex with one (complete edge and vertex fans), and those whose boxes touch a
/// changed one's cubes (every possible intersection). Increasing order.
std::vector<std::uint32_t> neighbourhood_of(const Mesh& mesh, const std::vector<std::uint8_t>& changed, double cube,
                                            std::vector<std::uint8_t>& vertex_changed) {
    vertex_changed.assign(mesh.vertices.size(), 0);
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        if (!changed[t]) continue;
        for (std::uint32_t v : mesh.triangles[t]) vertex_changed[v] = 1;
    }
    const std::vector<std::uint64_t> keys = touched_cubes(mesh, changed, cube);
    std::vector<std::uint8_t> selected(mesh.triangles.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangles.size()), [&](const auto& range) {
        for (std::size_t t = range.begin(); t != range.end(); ++t) {
            const auto& tri = mesh.triangles[t];
            if (vertex_changed[tri[0]] || vertex_changed[tri[1]] || vertex_changed[tri[2]]) {
                selected[t] = 1;
                continue;
            }
            std::array<std::int64_t, 3> lo{}, hi{};
            cube_range(mesh, std::uint32_t(t), cube, lo, hi);
            for (std::int64_t x = lo[0]; x <= hi[0] && !selected[t]; ++x) {
                for (std::int64_t y = lo[1]; y <= hi[1] && !selected[t]; ++y) {
                    for (std::int64_t z = lo[2]; z <= hi[2] && !selected[t]; ++z) {
                        selected[t] = std::binary_search(keys.begin(), keys.end(), cube_key(x, y, z));
                    }
                }
            }
        }
    });
    std::vector<std::uint32_t> result;
    for (std::uint32_t t = 0; t < selected.size(); ++t) {
        if (selected[t]) result.push_back(t);
    }
    return result;
}

/// The listed triangles of @a mesh as a mesh of their own (vertices renumbered in order of
/// first use); @a vertex_of maps the new vertices back.
Mesh submesh(const Mesh& mesh, const std::vector<std::uint32_t>& triangles, std::vector<std::uint32_t>& vertex_of) {
    constexpr std::uint32_t kNone = ~std::uint32_t(0);
    std::vector<std::uint32_t> renumber(mesh.vertices.size(), kNone);
    Mesh sub;
    sub.triangles.reserve(triangles.size());
    vertex_of.clear();
    for (std::uint32_t t : triangles) {
        std::array<std::uint32_t, 3> tri{};
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.triangles[t][std::size_t(k)];
            if (renumber[v] == kNone) {
                renumber[v] = std::uint32_t(vertex_of.size());
                vertex_of.push_back(v);
                sub.vertices.push_back(mesh.vertices[v]);
            }
            tri[std::size_t(k)] = renumber[v];
        }
        sub.triangles.push_back(tri);
    }
    return sub;
}

/// Marks the triangles of @a mesh that are on a non-manifold edge or vertex (vertices
/// flagged in @a judged only, all when empty), on a vertex another one coincides with, or in
/// a self-intersecting pair.
void mark_broken(const Mesh& mesh, const std::vector<std::uint8_t>& judged, std::vector<std::uint8_t>& bad) {
    mark_nonmanifold_edges(mesh, bad);
    mark_nonmanifold_vertices(mesh, judged, bad);
    mark_coincident_vertices(mesh, bad);
    for (const auto& [a, b] : find_self_intersections(mesh)) {
        bad[a] = 1;
        bad[b] = 1;
    }
}

/// Flags in @a bad the triangles that are bad together with a @a changed one (see
/// triangles_to_refine()).
void mark_around(const DmcGrid& grid, const DmcContour& contour, double tolerance, const std::vector<std::uint8_t>& changed,
                 std::vector<std::uint8_t>& bad) {
    const Mesh& mesh = contour.mesh;
    // Cubes of 4 voxels: a triangle spans at most a few of them.
    const openvdb::Vec3d voxel = grid.grid->voxelSize();
    const double cube = 4.0 * std::max({voxel[0], voxel[1], voxel[2]});
    std::vector<std::uint8_t> vertex_changed;
    const std::vector<std::uint32_t> region = neighbourhood_of(mesh, changed, cube, vertex_changed);
    std::vector<std::uint32_t> vertex_of;
    const Mesh sub = submesh(mesh, region, vertex_of);
    std::vector<std::uint8_t> judged(sub.vertices.size());
    for (std::size_t v = 0; v < judged.size(); ++v) judged[v] = vertex_changed[vertex_of[v]];
    std::vector<std::uint8_t> sub_bad(sub.triangles.size(), 0);
    mark_broken(sub, judged, sub_bad);
    for (std::size_t i = 0; i < region.size(); ++i) bad[region[i]] = sub_bad[i];
    std::vector<std::uint32_t> changed_list;
    for (std::uint32_t t = 0; t < changed.size(); ++t) {
        if (changed[t]) changed_list.push_back(t);
    }
    mark_off_surface(grid, contour, tolerance, changed_list, bad);
}

/// Sets in @a voxels the voxels of the merged cell of @a octree holding voxel @a offset.
void mark_cell(const LeafOctree& octree, int offset, std::bitset<512>& voxels) {
    const int size = 1 << octree.level_at(offset), mask = ~(size - 1);
    const int x = (offset >> 6) & mask, y = ((offset >> 3) & 7) & mask, z = offset & 7 & mask;
    for (int i = 0; i < size; ++i) {
        for (int j = 0; j < size; ++j) {
            for (int k = 0; k < size; ++k) voxels.set(std::size_t(leaf_offset(x + i, y + j, z + k)));
        }
    }
}

/// Splits the merged cell of leaf @a leaf holding voxel @a offset, if any, recording it.
bool split_cell(std::vector<LeafOctree>& octrees, std::size_t leaf, int offset, SplitVoxels& split) {
    LeafOctree& octree = octrees[leaf];
    if (octree.level_at(offset) == 0) return false;
    mark_cell(octree, offset, split.voxels[leaf]);
    split.changed[leaf] = 1;
    octree.split_cell(offset);
    return true;
}

}  // namespace

std::vector<std::uint32_t> triangles_to_refine(const DmcGrid& grid, const DmcContour& contour, double tolerance,
                                               const SplitVoxels* since) {
    const Mesh& mesh = contour.mesh;
    std::vector<std::uint8_t> bad(mesh.triangles.size(), 0);
    if (since) {
        mark_around(grid, contour, tolerance, changed_triangles(grid, contour, *since), bad);
    } else {
        // Only triangles from merged cells are refined: the rest are judged only against them.
        std::vector<std::uint8_t> merged(mesh.triangles.size());
        for (std::size_t t = 0; t < merged.size(); ++t) merged[t] = contour.sources[t].merged;
        mark_around(grid, contour, tolerance, merged, bad);
    }
    std::vector<std::uint32_t> result;
    for (std::uint32_t t = 0; t < bad.size(); ++t) {
        if (bad[t] && contour.sources[t].merged) result.push_back(t);
    }
    return result;
}

bool split_cells_of(const DmcGrid& grid, const DmcContour& contour, const std::vector<std::uint32_t>& triangles,
                    std::vector<LeafOctree>& octrees, SplitVoxels& split) {
    split.voxels.assign(grid.leaves.size(), std::bitset<512>());
    split.changed.assign(grid.leaves.size(), 0);
    std::unordered_map<const FloatLeaf*, std::size_t> index_of;
    for (std::size_t i = 0; i < grid.leaves.size(); ++i) index_of.emplace(grid.leaves[i], i);
    auto accessor = grid.grid->getConstAccessor();
    bool any_split = false;
    for (std::uint32_t t : triangles) {
        const openvdb::Coord p = contour.sources[t].p;
        for (int c = 0; c < 8; ++c) {
            const openvdb::Coord voxel = p.offsetBy(c & 1, (c >> 1) & 1, c >> 2);
            const FloatLeaf* leaf = accessor.probeConstLeaf(voxel);
            if (!leaf) continue;
            const std::size_t index = index_of.at(leaf);
            const int offset = leaf_offset(voxel.x() & 7, voxel.y() & 7, voxel.z() & 7);
            any_split = split_cell(octrees, index, offset, split) || any_split;
        }
    }
    return any_split;
}

bool split_cells_at(const std::vector<LeafVoxel>& voxels, std::vector<LeafOctree>& octrees, SplitVoxels& split) {
    bool any_split = false;
    for (const LeafVoxel& v : voxels) {
        if (split.voxels[v.leaf][v.offset]) continue;  // split this round already
        any_split = split_cell(octrees, v.leaf, v.offset, split) || any_split;
    }
    return any_split;
}

}  // namespace vdbmesh::detail
