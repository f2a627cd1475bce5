#pragma once
// Private: intersection-free octree contouring (MeshMethod::dc), whole or by bricks of nodes
// (docs/dmc.md, "Bricks").

#include <openvdb/openvdb.h>

#include <vector>

#include "mesh/ifc_polygons.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::detail {

/// Dual Contouring on the octree of every 8^3 leaf with Marching Cubes in the unit cells
/// (ifc_octree.cpp merges, ifc_polygons.cpp triangulates), closed, manifold and free of
/// self-intersections by construction, at any options.error (0: Marching Cubes). Adds its
/// phases ("octree", "contour", "weld") to @a report.
Mesh intersection_free_contouring(const openvdb::FloatGrid& grid, const MeshOptions& options, MeshReport& report);

/// The same mesh, brick after brick of @a bricks.nodes_per_brick^3 nodes read from @a source
/// (options.error > 0). The same bytes for any brick size and thread count.
Mesh bricked_contouring(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks, MeshReport& report);

/// The same mesh into @a sink through a spill (ifc_spill.h), never held whole; with
/// @a mirrored every triangle wound the other way.
void bricked_contouring_to_stream(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks, bool mirrored,
                                  MeshStreamSink& sink, MeshReport& report);

/// The largest brick edge (nodes) whose brick_peak_bytes() fits in @a memory_bytes.
/// @throw UsageError naming the smallest limit that works when even one node does not fit.
int plan_brick_size(const GridRegionSource& source, std::uint64_t memory_bytes);

/// What the blocks of one node made: per block in origin order its vertices (coarse cells
/// taken out) and triangles, then the node's coarse cells, once each in key order.
struct IfcNodeOutput {
    openvdb::Coord origin;
    std::vector<IfcBlockOutput> blocks;
    std::vector<IfcVertex> coarse;
};

/// Whether node origin @a a comes before @a b in z-major order (z, then y, then x).
inline bool ifc_node_before(const openvdb::Coord& a, const openvdb::Coord& b) {
    return a.z() != b.z() ? a.z() < b.z() : a.y() != b.y() ? a.y() < b.y() : a.x() < b.x();
}

/// The contour of the blocks of @a grid (options.error > 0), per node in z-major order. With
/// @a owned (a box of whole nodes, inclusive): the octree and coarse merge of the blocks of the
/// nodes within one node of it, the contour of those inside it only; else of every block.
std::vector<IfcNodeOutput> contour_ifc_nodes(const openvdb::FloatGrid& grid, const SampleClassifier& classifier, const MeshOptions& options,
                                             const openvdb::CoordBBox* owned, MeshReport& report);

/// One vertex per key, numbered node after node in the order of @a nodes (z-major), the
/// triangles in the same order; vertices no triangle uses are dropped (ifc_weld.cpp).
Mesh weld_ifc_nodes(std::vector<IfcNodeOutput>&& nodes);

}  // namespace vdbmesh::detail
