#pragma once
// Private: Marching Cubes on the dual cells of the leaf octrees, vertices welded by dual edge.

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "mesh/dmc_grid.h"
#include "mesh/dmc_octree.h"
#include "vdbmesh/mesh.h"

namespace vdbmesh::detail {

/// Where a triangle came from: the dual cell at voxel corner p + 1/2.
struct TriangleSource {
    openvdb::Coord p;
    bool merged;  ///< a corner of the dual cell is a merged octree cell (not a voxel)
};

struct DmcContour {
    Mesh mesh;                            ///< world coordinates
    std::vector<TriangleSource> sources;  ///< per triangle (when asked for)
    std::vector<std::size_t> first_triangle;  ///< per leaf, its first triangle; one more: the count
};

/// A mesh vertex as one leaf refers to it (its owner leaf and edge slot; dmc_contour.cpp).
using DmcVertexRef = std::uint32_t;

/// One leaf's triangles, before vertices are numbered.
struct DmcLeafTriangles {
    std::vector<std::array<DmcVertexRef, 3>> triangles;
    std::vector<TriangleSource> sources;  ///< only when asked for
};

/// Per-leaf triangles kept between calls of contour_dual_cells(): after the octrees of a few
/// leaves changed, only the leaves next to them are contoured again.
struct DmcContourCache {
    std::vector<DmcLeafTriangles> per_leaf;  ///< empty: nothing kept yet
    std::vector<std::uint8_t> changed;       ///< per leaf: its octree changed since the last call
};

/// Contours every dual cell of @a octrees with the shared Marching Cubes table. A mesh vertex
/// sits on a dual edge (two face-adjacent octree cells) at the linear crossing between their
/// vertices (edge_crossing.h); it is identified by the edge, so welding is exact. Triangles
/// with a repeated vertex (degenerate dual cells) are dropped. Deterministic: leaves in tree
/// order, cells in voxel order, counts then prefix sums then fills. Sources are filled only
/// when @a with_sources. With @a cache (the same @a with_sources on every call), leaves whose
/// 27 neighbours kept their octrees reuse their triangles from the previous call.
DmcContour contour_dual_cells(const DmcGrid& grid, const std::vector<LeafOctree>& octrees, bool with_sources,
                              const std::function<void(double)>& progress, DmcContourCache* cache = nullptr);

}  // namespace vdbmesh::detail
