#pragma once
// Private: intersection-free octree contouring (MeshMethod::dc), whole or by bricks of nodes
// (docs/dmc.md, "Bricks").

#include <openvdb/openvdb.h>

#include <functional>
#include <optional>
#include <vector>

#include "mesh/dc_block.h"
#include "mesh/dc_polygons.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::detail {

/// Dual Contouring on the octree of every 8^3 leaf with Marching Cubes in the unit cells
/// (dc_octree.cpp merges, dc_polygons.cpp triangulates), closed, manifold and free of
/// self-intersections by construction, at any options.error (0: no merging, a vertex per unit
/// cell whose surface is one disk, docs/dmc.md "Error 0"). Adds its
/// phases ("octree", "contour", "weld") to @a report.
Mesh intersection_free_contouring(const openvdb::FloatGrid& grid, const MeshOptions& options, MeshReport& report);

/// The same mesh, brick after brick of @a bricks.shape read from @a source
/// (with MeshMethod::mc, Marching Cubes by bricks: marching_cubes_nodes()). The same bytes for any brick size and thread count.
Mesh bricked_contouring(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks, MeshReport& report);

/// The same mesh into @a sink through a spill (dc_spill.h), never held whole; with
/// @a mirrored every triangle wound the other way.
void bricked_contouring_to_stream(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks, bool mirrored,
                                  MeshStreamSink& sink, MeshReport& report);

/// A brick (docs/dmc.md, "Bricks"): its shape's nodes across from (min_x, min_y) (voxels), and one
/// node high, at node layer @a layer (z / kNodeVoxels); with the active voxels of its nodes,
/// which ranks are balanced by.
struct IfcBrick {
    int min_x = 0, min_y = 0, layer = 0;
    std::uint64_t active_voxels = 0;
};

/// The bricks of @a shape holding a node that may hold surface, in visiting order: columns in
/// (y, x) order, each column's layers bottom to top without gaps.
std::vector<IfcBrick> plan_ifc_bricks(const GridRegionSource& source, const BrickShape& shape);

/// Without a limit (@a memory_bytes 0), one column holding every node; else, of the shapes
/// whose brick_peak_bytes() fits, the one whose rings build the least octree twice.
/// @throw UsageError naming the smallest limit that works when even one node does not fit.
BrickShape plan_brick_shape(const GridRegionSource& source, std::uint64_t memory_bytes);

/// What the blocks of one node made: per block in origin order its vertices (coarse cells
/// taken out) and triangles, then the node's coarse cells, once each in key order.
struct IfcNodeOutput {
    openvdb::Coord origin;
    std::vector<IfcBlockOutput> blocks;
    std::vector<IfcVertex> coarse;
};

/// The origin of the node (docs/dmc.md, "Bricks") holding grid point @a p.
inline openvdb::Coord ifc_node_of(const openvdb::Coord& p) {
    constexpr int kNodeMask = ~(kNodeVoxels - 1);
    return openvdb::Coord(p.x() & kNodeMask, p.y() & kNodeMask, p.z() & kNodeMask);
}

/// Whether node origin @a a comes before @a b in z-major order (z, then y, then x).
inline bool ifc_node_before(const openvdb::Coord& a, const openvdb::Coord& b) {
    return a.z() != b.z() ? a.z() < b.z() : a.y() != b.y() ? a.y() < b.y() : a.x() < b.x();
}

/// Gives the pages of freed small allocations back to the system (glibc's malloc_trim).
void release_free_memory();

/// Which block origins a stage of the contouring takes (every block when empty).
using IfcOriginFilter = std::function<bool(const openvdb::Coord&)>;

/// The cells of the blocks of @a grid that may hold surface, with origins @a within (every
/// block when not given) in the nodes @a build_node accepts (every node when null): each
/// block's octree, then each node's coarse merge (dc_coarse_merge.cpp; @a within must hold
/// every block of a node or none). Adds the phases "octree" and "coarse" to @a report.
IfcCellGrid build_ifc_cell_grid(const openvdb::FloatGrid& grid, const SampleClassifier& classifier, const MeshOptions& options,
                                const std::optional<openvdb::CoordBBox>& within, MeshReport& report,
                                const IfcOriginFilter& build_node = {});

/// Splits the blocks that are still one 8-voxel cell of their own after the merge across
/// blocks, whose surface only clips one of their faces, where the block across that face is not
/// one cell as large: their cells become the ones the octree kept for that
/// (IfcBlockCells::Parts). The triangles over the clipped face would join the cell's vertex,
/// about 4 voxels away, to a chord or to segments under a voxel or two long. Next to a cell as
/// large, or inside a coarse cell, a block stays whole: splitting there too cost the sphere of
/// DcTest 32% more triangles. Engine at --error 0.5 / 1, angles under 10 degrees: 0.64% / 0.63%
/// -> 0.49% / 0.45%, triangles +0.2% / +1.9% (docs/dmc.md, "Session 12").
/// Decides the blocks not yet decided whose origins @a decide accepts (each reads its 26
/// neighbours as the coarse merge left them, IfcBlockCells::was_split), so blocks may be decided
/// in any order and in any number of calls with the same result.
void split_clipped_blocks(IfcCellGrid& cells, const IfcOriginFilter& decide);

/// The triangles and keyed vertices of the blocks of @a cells whose origins @a own accepts, in
/// the order of cells.origins (empty for the others). Adds the phase "contour" to @a report.
std::vector<IfcBlockOutput> contour_ifc_cells(const openvdb::FloatGrid& grid, const SampleClassifier& classifier, const MeshOptions& options,
                                              const IfcCellGrid& cells, const IfcOriginFilter& own, MeshReport& report);

/// The blocks' outputs (in the order of @a origins) grouped by node, nodes in z-major order,
/// blocks in origin order inside each; the coarse cells each block lists (every block a coarse
/// cell covers lists it, all in its node) taken out, once each per node in key order. Each
/// block's output is moved, not copied; blocks with no output are skipped.
std::vector<IfcNodeOutput> group_ifc_outputs_by_node(const std::vector<openvdb::Coord>& origins, std::vector<IfcBlockOutput>& outputs);

/// The contour of every block of @a grid, per node in z-major order.
std::vector<IfcNodeOutput> contour_ifc_nodes(const openvdb::FloatGrid& grid, const SampleClassifier& classifier, const MeshOptions& options,
                                             MeshReport& report);

/// One vertex per key, numbered node after node in the order of @a nodes (z-major), the
/// triangles in the same order; vertices no triangle uses are dropped (dc_weld.cpp).
Mesh weld_ifc_nodes(std::vector<IfcNodeOutput>&& nodes);

}  // namespace vdbmesh::detail
