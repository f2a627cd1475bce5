// The coverage check of Dual Marching Cubes (see dmc_coverage_check.h): the crossings of the
// isosurface with the grid edges in each merged cell, against a bounding-volume hierarchy of
// the mesh's triangles, each query bounded by the tolerance.

#include "mesh/dmc_coverage_check.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "vdbmesh/geometry.h"
#include "mesh/edge_crossing.h"

namespace vdbmesh::detail {

namespace {

/// The mesh near the surface, queried in world units.
struct MeshNearness {
    const Mesh& mesh;
    const TriangleBvh& bvh;
    const openvdb::math::Transform& transform;
    double radius_squared;  ///< the tolerance in world units, squared

    /// Whether a triangle lies within the tolerance of @a index_point. @a hint, the triangle
    /// found last (crossings of one cell are mostly near one triangle), is tried first.
    bool covers(const Point3d& index_point, std::uint32_t& hint) const {
        const openvdb::Vec3d w = transform.indexToWorld(openvdb::Vec3d(index_point[0], index_point[1], index_point[2]));
        const Point3 p = {w[0], w[1], w[2]};
        if (hint < mesh.triangles.size() && bvh.closest_on_triangle(p, hint).distance_squared < radius_squared) return true;
        const ClosestPoint closest = bvh.closest_point(p, radius_squared);
        if (!(closest.distance_squared < radius_squared)) return false;
        hint = closest.triangle;
        return true;
    }
};

/// Whether every crossing of a grid edge with the isosurface inside the cell of @a size voxels
/// whose minimum voxel is local (x, y, z) lies near the mesh. Edges from the cell's samples
/// and the ring below it are walked; a crossing counts where it lies in the cell's box.
bool cell_covered(const DmcGrid& grid, const SampleBlock& block, int x, int y, int z, int size, const MeshNearness& mesh) {
    const Point3d lo = {x - 0.5, y - 0.5, z - 0.5}, hi = {x + size - 0.5, y + size - 0.5, z + size - 0.5};
    std::uint32_t hint = ~std::uint32_t(0);
    for (int i = x - 1; i < x + size; ++i) {
        for (int j = y - 1; j < y + size; ++j) {
            for (int k = z - 1; k < z + size; ++k) {
                const double a = block.at(i, j, k);
                const bool a_inside = block.inside[std::size_t(SampleBlock::index(i, j, k))];
                for (int axis = 0; axis < 3; ++axis) {
                    const int di = axis == 0, dj = axis == 1, dk = axis == 2;
                    if (block.inside[std::size_t(SampleBlock::index(i + di, j + dj, k + dk))] == a_inside) continue;
                    const double b = block.at(i + di, j + dj, k + dk);
                    if (!std::isfinite(a) || !std::isfinite(b)) continue;
                    const Point3d c = edge_crossing({double(i), double(j), double(k)}, a,
                                                    {double(i + di), double(j + dj), double(k + dk)}, b, grid.iso);
                    bool in_cell = true;
                    for (std::size_t n = 0; n < 3; ++n) in_cell = in_cell && c[n] >= lo[n] && c[n] <= hi[n];
                    if (!in_cell) continue;
                    const openvdb::Coord o = block.origin;
                    if (!mesh.covers({o.x() + c[0], o.y() + c[1], o.z() + c[2]}, hint)) return false;
                }
            }
        }
    }
    return true;
}

/// Calls @a visit(holder leaf, offset) for the voxels of the 3^3 neighbourhood of local voxel
/// (x, y, z) of leaf @a leaf that lie in merged cells.
template <typename Visit>
void for_each_merged_neighbour(const DmcGrid& grid, const std::vector<LeafOctree>& octrees, std::size_t leaf, int x, int y,
                               int z, Visit&& visit) {
    for (int n = 0; n < 27; ++n) {
        const int i = x + n / 9 - 1, j = y + n / 3 % 3 - 1, k = z + n % 3 - 1;
        const std::int32_t holder = grid.leaf_at(leaf, i, j, k);
        if (holder < 0) continue;
        const int offset = leaf_offset(i & 7, j & 7, k & 7);
        if (octrees[std::size_t(holder)].level_at(offset) > 0) visit(std::uint32_t(holder), std::uint16_t(offset));
    }
}

/// The merged cells to split for leaf @a leaf: its own merged cells holding a crossing far
/// from the mesh, and the merged cells around its voxels (unit cells) holding one: their
/// triangles make the surface there.
void judge_leaf(const DmcGrid& grid, const std::vector<LeafOctree>& octrees, std::size_t leaf, const SampleBlock& block,
                const MeshNearness& nearness, std::vector<LeafVoxel>& out) {
    const LeafOctree& octree = octrees[leaf];
    for (const std::uint16_t min : octree.merged_min) {
        const int size = 1 << octree.level_at(min);
        if (!cell_covered(grid, block, min >> 6, (min >> 3) & 7, min & 7, size, nearness)) out.push_back({std::uint32_t(leaf), min});
    }
    for (int offset = 0; offset < 512; ++offset) {
        if (octree.level_at(offset) != 0) continue;
        const int x = offset >> 6, y = (offset >> 3) & 7, z = offset & 7;
        bool near_merged = false;
        for_each_merged_neighbour(grid, octrees, leaf, x, y, z, [&](std::uint32_t, std::uint16_t) { near_merged = true; });
        if (!near_merged || cell_covered(grid, block, x, y, z, 1, nearness)) continue;
        for_each_merged_neighbour(grid, octrees, leaf, x, y, z, [&](std::uint32_t holder, std::uint16_t voxel) { out.push_back({holder, voxel}); });
    }
}

/// Per leaf, whether its cells are judged: those next to merged cells, and without @a since
/// every such leaf, with it only those next to a leaf it changed.
std::vector<std::uint8_t> leaves_to_judge(const DmcGrid& grid, const std::vector<LeafOctree>& octrees, const SplitVoxels* since) {
    std::vector<std::uint8_t> judged(grid.leaves.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, judged.size()), [&](const auto& range) {
        for (std::size_t leaf = range.begin(); leaf != range.end(); ++leaf) {
            judged[leaf] = neighbourhood_has_merges(grid, octrees, leaf) &&
                           (!since || grid.any_neighbour(leaf, [&](std::size_t n) { return since->changed[n]; }));
        }
    });
    return judged;
}

/// The triangles that can lie near a point of a judged leaf: those of the dual cells owned by
/// its neighbours (a dual cell's corners are cells holding voxels of its owner or the next
/// leaf, and a cell stays within its leaf).
std::vector<std::uint32_t> triangles_near(const DmcGrid& grid, const DmcContour& contour, const std::vector<std::uint8_t>& judged) {
    std::vector<std::uint32_t> triangles;
    for (std::size_t leaf = 0; leaf < judged.size(); ++leaf) {
        if (!grid.any_neighbour(leaf, [&](std::size_t n) { return judged[n] != 0; })) continue;
        for (std::size_t t = contour.first_triangle[leaf]; t < contour.first_triangle[leaf + 1]; ++t) triangles.push_back(std::uint32_t(t));
    }
    return triangles;
}

}  // namespace

std::vector<LeafVoxel> cells_missing_surface(const DmcGrid& grid, const std::vector<LeafOctree>& octrees,
                                             const DmcContour& contour, double tolerance, const SplitVoxels* since) {
    const std::vector<std::uint8_t> judged = leaves_to_judge(grid, octrees, since);
    std::vector<std::uint32_t> nearby = triangles_near(grid, contour, judged);
    if (nearby.empty()) return {};
    const Mesh& mesh = contour.mesh;
    const TriangleBvh bvh(mesh, std::move(nearby));
    const openvdb::Vec3d voxel = grid.grid->voxelSize();
    // The smallest voxel edge: a point this near in world units is at most this near in voxels.
    const double radius = tolerance * std::min({voxel[0], voxel[1], voxel[2]});
    const MeshNearness nearness{mesh, bvh, grid.grid->transform(), radius * radius};
    std::vector<std::vector<LeafVoxel>> per_leaf(grid.leaves.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid.leaves.size()), [&](const auto& range) {
        auto block = std::make_unique<SampleBlock>();
        for (std::size_t leaf = range.begin(); leaf != range.end(); ++leaf) {
            if (!judged[leaf]) continue;
            load_sample_block(grid, leaf, *block);
            judge_leaf(grid, octrees, leaf, *block, nearness, per_leaf[leaf]);
        }
    });
    std::vector<LeafVoxel> result;
    for (const auto& cells : per_leaf) result.insert(result.end(), cells.begin(), cells.end());
    return result;
}

}  // namespace vdbmesh::detail
