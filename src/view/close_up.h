#pragma once
// The page's switch from splats to triangles: where a view asks for more detail than the
// finest splats hold, and the full mesh there has fewer triangles than the discs that detail
// would take, the page shows the full mesh's triangles of a box round those splats (GET
// /api/mesh?level=region) and the splats elsewhere.

#include <cstddef>
#include <optional>

#include "vdbmesh/grid_region.h"
#include "vdbmesh/openvdb_fwd.h"
#include "vdbmesh/splats.h"

namespace vdbmesh::view {

/// Triangles of a mesh per edge crossing of the grid: a closed surface has about twice as many
/// triangles as vertices, and Marching Cubes (and DC at error 0) make about one vertex per
/// crossing. A splat node's weight counts its crossings (on shared faces twice), so twice the
/// weight bounds the triangles its cube gives from above.
inline constexpr std::size_t kTrianglesPerCrossing = 2;
/// Close-up boxes are snapped outward to multiples of this many voxels, so that small camera
/// moves ask for the same box (the server keeps the meshes it made).
inline constexpr std::int32_t kCloseUpSnapVoxels = 32;

/// A box of the grid whose triangles the page should draw instead of splats.
struct CloseUp {
    IndexBox box;                         ///< index space, min inclusive, max exclusive
    std::size_t estimated_triangles = 0;  ///< of the full mesh with a corner in the box (upper estimate)
    std::size_t nodes = 0;                ///< selected nodes that asked for triangles
};

/// Close-up boxes span at most this many voxels on each axis (before snapping): one node's
/// width, so that the nodes a close-up reads round it stay within its read cap on a dense scan.
inline constexpr std::int32_t kCloseUpMaxVoxels = kNodeVoxels;

/// Whether a node of @a selection asks for triangles: its disc spans d pixels on screen, and the
/// (d / pixel_size)^2 discs of pixel_size that would show its surface at the detail the view
/// asks for are more than the kTrianglesPerCrossing x weight triangles of the mesh there. The
/// box holds such nodes, the most pressing first, as long as it spans at most
/// kCloseUpMaxVoxels (their spheres, in the index space of @a grid's transform), then is
/// snapped outward to kCloseUpSnapVoxels. None when no node asks, or when the box's
/// triangles, estimated from the tree, exceed @a max_triangles.
std::optional<CloseUp> find_close_up(const SplatTree& tree, const SplatSelection& selection, const SplatView& view,
                                     const openvdb::FloatGrid& grid, std::size_t max_triangles);

/// Moves the nodes of @a selection whose centre lies in @a box (index space of @a grid) to its end,
/// each part keeping its order; returns how many moved (the splats the close-up replaces).
std::size_t move_inside_last(const SplatTree& tree, const IndexBox& box, const openvdb::FloatGrid& grid,
                             SplatSelection& selection);

}  // namespace vdbmesh::view
