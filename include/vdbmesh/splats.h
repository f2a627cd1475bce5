#pragma once
/// @file splats.h
/// @brief The splat hierarchy of a grid's isosurface (seed 004, section 5; QSplat, Rusinkiewicz
/// and Levoy 2000): what the viewer shows of a model too large to mesh. Built from the grid's
/// samples alone (no mesh). OpenVDB-free: grids are only declared.
///
/// The tree is an octree aligned with the VDB tree. A node of level L covers a cube of
/// 2^(L+1) voxels: level 0 is the finest (2^3 voxels), level 2 a leaf (8^3), level 6 a
/// level-1 internal node (128^3), level 11 a level-2 internal node (4096^3); the root
/// (kSplatRootLevel) joins those. A finest node's splat is the least-squares plane through the
/// isosurface's crossings of the grid edges inside its cube (closed: crossings on a shared
/// face belong to both cubes, so neighbouring splats meet), its radius reaching the farthest
/// crossing. An inner node's splat is the crossing-weighted mean of its children's, its radius
/// enclosing theirs and its normal cone their cones.

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vdbmesh/mesher.h"
#include "vdbmesh/openvdb_fwd.h"

namespace vdbmesh {

class GridRegionSource;

/// The level of the root node (one above the 4096^3 internal nodes).
inline constexpr std::uint8_t kSplatRootLevel = 12;
/// The level of a node covering a VDB leaf (8^3 voxels).
inline constexpr std::uint8_t kSplatLeafLevel = 2;

/// One node of the hierarchy, in the grid's world space.
struct SplatNode {
    std::array<float, 3> centre{};
    float radius = 0;              ///< the disc covers the surface of the whole subtree
    std::array<float, 3> normal{}; ///< unit, pointing out of the object
    float cone = 0;                ///< half-angle (radians) of the cone around normal holding every normal below
    std::uint32_t first_child = 0; ///< index of the first child; the children are contiguous
    std::uint32_t child_count = 0;
    std::uint32_t weight = 0;      ///< edge crossings the subtree was fitted to (saturated)
    std::uint8_t level = 0;
};

/// What identifies the .vdb a tree was fitted to, read without reading its voxels (which
/// takes a pass over the whole file: a minute for a huge scan): its size, the checksum its
/// metadata states (vdbmesh's own files: over the tree's values, transform and metadata, as
/// written), its modification time when it states none, and a hash of its topology (every
/// 128^3 node's origin and active voxel count) with its transform and background.
struct SplatGridId {
    std::uint64_t file_bytes = 0;
    std::string checksum;         ///< vdbmesh_checksum as stated; empty: none stated
    std::int64_t modified = 0;    ///< the file's modification time (ns since its clock's epoch) when no checksum is stated, else 0
    std::uint64_t topology = 0;   ///< FNV-1a over the nodes, the transform's matrix and the background
    bool operator==(const SplatGridId& other) const {
        return file_bytes == other.file_bytes && checksum == other.checksum && modified == other.modified &&
               topology == other.topology;
    }
    bool operator!=(const SplatGridId& other) const { return !(*this == other); }
};

/// The identity of the .vdb at @a path opened as @a source (open_vdb_regions(path)).
SplatGridId splat_grid_id(const std::filesystem::path& path, const GridRegionSource& source);

/// What differs between the grid a tree was fitted to and another, in words ("the grid it was
/// fitted to states checksum 9b3a206e27fd98fa, this one 14c5f29f3f13a4be"); empty when the same.
std::string splat_grid_difference(const SplatGridId& fitted, const SplatGridId& grid);

/// A splat hierarchy: nodes in breadth-first order, nodes[0] the root (empty tree: no nodes).
struct SplatTree {
    std::vector<SplatNode> nodes;
    double iso = 0;
    Inside inside = Inside::above;
    double tolerance = 0;  ///< SplatOptions::coplanar_tolerance it was built with
    SplatGridId grid;      ///< the .vdb it was fitted to, when the caller set it (kept in its file)
    /// The finest level the tree keeps: above 0 when the levels below were pruned to fit
    /// SplatOptions::max_bytes (their nodes dropped, this level's nodes childless).
    std::uint8_t finest_kept = 0;

    /// Nodes without children (what the finest view shows).
    std::size_t leaf_count() const;
};

struct SplatOptions {
    double iso = 0;                ///< isovalue, in the grid's value units
    Inside inside = Inside::above;
    /// Children are dropped where every child's disc lies within this many voxels of their
    /// parent's plane (and the children have no children of their own); only up to leaf level
    /// (8^3 voxels), so a collapsed splat never reaches over neighbouring structure. 0: never.
    double coplanar_tolerance = 0.1;
    /// build_splat_tree() by region only: the most its nodes may hold while they are built,
    /// at kSplatBuildBytesPerNode a node (0: no bound). Past it, the finest level kept is
    /// pruned (its nodes dropped, their parents made childless), down to leaf level
    /// (kSplatLeafLevel: a splat per 8^3 cell); the tree is then the unbounded tree with the
    /// levels under SplatTree::finest_kept removed, whatever the thread count.
    /// @throw Error (from the build) when even the tree down to leaf level exceeds it.
    std::uint64_t max_bytes = 0;
};

/// The bytes a node of a splat tree built by region holds at most while it is built: its
/// node under construction, and, while the tree is laid out, its SplatNode and its place in
/// the layout (a level's node vector that reallocates as it grows holds twice its nodes for
/// a moment: at most the same).
inline constexpr std::uint64_t kSplatBuildBytesPerNode = 116;

/// The splat hierarchy of @a grid's isosurface. Samples outside the grid's scan box are
/// outside the object (the surface closes there, at the edge's midpoint, as the meshers do).
/// Threaded with TBB; the same tree for any thread count. Throws UsageError on a negative
/// tolerance.
SplatTree build_splat_tree(const openvdb::FloatGrid& grid, const SplatOptions& options);

/// The same tree read by region: one 128^3 node at a time (its cells fitted in parallel), so
/// that only a node's region and the splats are held, never the whole grid.
SplatTree build_splat_tree(const GridRegionSource& source, const SplatOptions& options);

/// A coarse picture of @a source's surface from its topology alone, before any sample is
/// read (a .vdb's source lists its leaves' masks from the tree read at opening): a splat per
/// leaf holding active voxels, at their centroid, across their thinnest direction, its radius
/// reaching the farthest; inner nodes as build_splat_tree()'s. For grids whose active voxels
/// are a band round the surface (vdbmesh convert's). The normals' sign is unknown: every
/// node's cone is the whole sphere (never culled as facing away); iso is 0, tolerance 0.
SplatTree build_topology_preview(const GridRegionSource& source);

/// A camera, as the page sends it.
struct SplatView {
    /// World to clip space, column-major as WebGL takes it (three.js projectionMatrix times
    /// matrixWorldInverse).
    std::array<double, 16> view_projection{};
    std::array<double, 3> eye{};   ///< the camera's position, for back-face culling by the cones
    double focal_pixels = 600;     ///< pixels per world unit at clip w = 1 (viewport height / (2 tan(fov / 2)))
    double pixel_size = 2;         ///< a node is refined while its disc spans more pixels than this
    std::size_t budget = 200'000;  ///< at most this many nodes
};

/// What a view shows of a tree.
struct SplatSelection {
    std::vector<std::uint32_t> nodes;  ///< ascending node indices, none an ancestor of another
    std::uint8_t finest_level = kSplatRootLevel;  ///< the lowest level among them
    /// The highest level among them of a node shown in place of its children (too small on
    /// screen to refine, or over the budget); -1 when every node shown is childless (the view
    /// is at the tree's full detail).
    int cut_level = -1;
    /// No node was kept coarser than pixel_size for want of budget (the view is at full detail).
    bool complete = true;
};

/// The diameter of @a node's disc on @a view's screen, in pixels (unbounded when the eye is
/// inside its sphere).
double projected_splat_size(const SplatNode& node, const SplatView& view);

/// The nodes a view needs: from the root down, largest projected disc first, refined while it
/// spans more than pixel_size and the budget allows; nodes outside the view frustum or whose
/// normal cone faces wholly away from the eye are left out.
SplatSelection select_splats(const SplatTree& tree, const SplatView& view);

/// Writes @a tree quantised (12 bytes a node: centres in 16 bits over the tree's bounding
/// box, radii rounded up so that discs still cover what they covered, octahedral normals in
/// 16 bits, cones widened by the normals' rounding; then 2 bytes a childless node: its
/// weight), with the tree's SplatGridId, through a temporary file renamed over @a path.
/// Throws Error when it cannot be written.
void write_splat_file(const SplatTree& tree, const std::filesystem::path& path);

/// Reads a file of write_splat_file(). Throws FormatError naming the file and the field.
SplatTree read_splat_file(const std::filesystem::path& path);

namespace detail {
/// The largest angle (radians) between a unit vector and its 16-bit octahedral encoding.
inline constexpr double kSplatNormalRounding = 0.02;
/// A unit vector to 8 + 8 bits (octahedral map) and back.
std::array<std::uint8_t, 2> encode_splat_normal(const std::array<float, 3>& normal);
std::array<float, 3> decode_splat_normal(const std::array<std::uint8_t, 2>& code);
}  // namespace detail

}  // namespace vdbmesh
