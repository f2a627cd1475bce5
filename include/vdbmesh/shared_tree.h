#pragma once
/// @file shared_tree.h
/// @brief A shared (hash-consed) tree over the levels of OpenVDB's float tree, after Parker
/// and Udeshi, "Exploiting Self-Similarity in Geometry for Voxel Based Solid Modeling": every
/// distinct 8^3 leaf (values and active mask, compared bit for bit) and every distinct 16^3 and
/// 32^3 internal node (children and tiles) is stored once, so a periodic lattice of 4096^3
/// voxels takes megabytes. Operations on it (shared_ops below) use result matching: a result
/// is computed once per distinct node (with the neighbours it reads) and looked up after that.
///
/// OpenVDB-free: grids are only declared (openvdb_fwd.h).
///
/// Node ids are assigned in the order of first occurrence in a fixed (sorted) walk, so the same
/// input gives the same tree, byte for byte, whatever the thread count.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "vdbmesh/mesh.h"
#include "vdbmesh/openvdb_fwd.h"

namespace vdbmesh {

using Coord3 = std::array<int, 3>;

/// A child of a node: a node of the level below (its index in that level's table) or, with
/// kSharedTile set, a constant tile (its index in SharedTree::tiles, the low 31 bits).
using SharedRef = std::uint32_t;
inline constexpr SharedRef kSharedTile = 0x80000000u;
inline bool is_tile(SharedRef ref) { return (ref & kSharedTile) != 0; }
inline SharedRef tile_ref(std::uint32_t index) { return index | kSharedTile; }

/// Node sizes in voxels per axis, level 0 (leaf), 1, 2 (OpenVDB's Tree4<float, 5, 4, 3>).
inline constexpr int kSharedDim[3] = {8, 128, 4096};
/// Children per axis of a level-1 and level-2 node.
inline constexpr int kSharedChildren[3] = {8, 16, 32};

struct SharedTile {
    float value = 0;
    bool active = false;
};

/// An 8^3 leaf: values and active mask, voxel (x, y, z) at index (x * 8 + y) * 8 + z (as OpenVDB).
struct SharedLeaf {
    std::array<float, 512> values{};
    std::array<std::uint64_t, 8> active{};
    bool is_active(int index) const { return (active[index >> 6] >> (index & 63)) & 1u; }
    void set_active(int index, bool on) {
        if (on) active[index >> 6] |= std::uint64_t(1) << (index & 63);
        else active[index >> 6] &= ~(std::uint64_t(1) << (index & 63));
    }
};

/// An internal node: its children (level 1: 16^3 leaf refs, level 2: 32^3 level-1 refs),
/// child (x, y, z) at index (x * n + y) * n + z.
struct SharedNode {
    std::vector<SharedRef> children;
};

/// A top-level entry: the origin (a multiple of 4096) of a level-2 node or tile.
struct SharedRootEntry {
    Coord3 origin{};
    SharedRef ref = 0;
};

class SharedTree {
public:
    double voxel_size = 1.0;  ///< world units per voxel (uniform scale, no translation)
    float background = 0.0f;  ///< the value outside every root entry (inactive)
    bool level_set = true;    ///< values are signed distances, negative inside
    std::vector<SharedTile> tiles;    ///< distinct tiles; tiles[0] is the inactive background
    std::vector<SharedLeaf> leaves;   ///< distinct leaves (level 0)
    std::vector<SharedNode> nodes1;   ///< distinct level-1 nodes
    std::vector<SharedNode> nodes2;   ///< distinct level-2 nodes
    std::vector<SharedRootEntry> root;  ///< sorted by origin (x, then y, then z)

    /// The ref of the root entry at @a origin, or the background tile.
    SharedRef root_ref(const Coord3& origin) const;
};

/// A field evaluated one leaf at a time: what build_shared_tree() samples. Implementations are
/// called concurrently and must be deterministic.
class LeafField {
public:
    virtual ~LeafField() = default;
    virtual float background() const = 0;
    virtual double voxel_size() const = 0;
    /// The voxel box (inclusive) outside which every voxel is the inactive background.
    virtual std::array<Coord3, 2> bounds() const = 0;
    /// Values and active mask of the leaf at @a origin (a multiple of 8).
    virtual void evaluate(const Coord3& origin, SharedLeaf& leaf) const = 0;
    /// When the cube of @a dim voxels at @a origin is known to hold one value everywhere,
    /// sets @a tile and returns true (saves evaluating it). Default: unknown.
    virtual bool uniform_region(const Coord3& origin, int dim, SharedTile& tile) const;
    /// Periodic fields: the axes (bit a for axis a) along which the cube of @a dim voxels at
    /// @a origin repeats with the field's period, and in @a key its origin with those
    /// coordinates reduced by the period (the others as they are). Cubes given the same key
    /// and axes must hold exactly the same values; build_shared_tree() evaluates one of them.
    /// Default: 0 (no repetition known).
    virtual unsigned periodic_key(const Coord3& origin, int dim, Coord3& key) const;
};

/// Builds the shared tree of @a field bottom-up in parallel, evaluating each distinct
/// (canonical) leaf once and never materialising the voxels it represents.
SharedTree build_shared_tree(const LeafField& field);
/// The shared tree of a grid (its leaves, tiles and background; the transform must be a
/// uniform scale without translation). @throw UsageError otherwise.
SharedTree build_shared_tree(const openvdb::FloatGrid& grid);
/// The FloatGrid the tree represents (leaves and tiles expanded), level-set class when level_set.
std::shared_ptr<openvdb::FloatGrid> to_float_grid(const SharedTree& tree);

/// Nodes stored against nodes represented, per level (0 leaves, 1, 2), and the memory.
struct SharedStats {
    std::array<std::uint64_t, 3> stored{};       ///< distinct nodes per level
    std::array<std::uint64_t, 3> represented{};  ///< nodes per level in the expanded tree
    std::uint64_t tiles = 0;                     ///< distinct tiles
    std::uint64_t root_entries = 0;
    std::uint64_t shared_bytes = 0;     ///< memory of the shared tree
    std::uint64_t expanded_bytes = 0;   ///< memory of the same nodes unshared (OpenVDB's layout, roughly)
    std::uint64_t active_voxels = 0;
};
SharedStats shared_stats(const SharedTree& tree);

// ---- Operations with result matching (and their plain references on a FloatGrid) -------------

/// Active voxels, tiles included.
std::uint64_t shared_active_voxels(const SharedTree& tree);
/// Volume of a level set (world units^3): each voxel counts clamp(0.5 - value / voxel, 0, 1)
/// of its cube, tiles their whole cube when inside.
double shared_volume(const SharedTree& tree);
/// Area (world units^2) of the Marching Cubes surface at value 0 (inside: below), the
/// surface that shared_marching_cubes() and mesh_grid(MeshMethod::mc) make.
double shared_area(const SharedTree& tree);
/// Connected components (6-connected) of the inside voxels (value < 0).
std::uint64_t shared_components(const SharedTree& tree);

/// Marching Cubes (inside below 0, the case table and crossing rule of mesh_grid's MC) with
/// each 8^3 block's result computed once per distinct neighbourhood and translated: the same
/// welded mesh, triangle for triangle, as mesh_grid(grid, {mc, iso 0, inside below}).
Mesh shared_marching_cubes(const SharedTree& tree);

/// The same surface as distinct block meshes placed by translations (for instanced output).
struct InstancedMesh {
    std::vector<Mesh> parts;  ///< vertices in world units relative to the block's origin
    struct Instance {
        std::uint32_t part = 0;
        std::array<double, 3> translation{};  ///< world units
    };
    std::vector<Instance> instances;  ///< sorted by block origin
};
InstancedMesh shared_marching_cubes_instanced(const SharedTree& tree);

/// Plain references: the same figures computed voxel by voxel on a grid.
std::uint64_t plain_active_voxels(const openvdb::FloatGrid& grid);
double plain_volume(const openvdb::FloatGrid& grid);
/// Components of the inside voxels (value < 0) over the grid's whole extent.
std::uint64_t plain_components(const openvdb::FloatGrid& grid);
/// The same over the voxel box @a box (inclusive); @a periodic: each face also touches the
/// opposite one (the box extended periodically).
std::uint64_t plain_components(const openvdb::FloatGrid& grid, const std::array<Coord3, 2>& box, bool periodic);

/// The components of a periodic field cut by a box, found by plain labellings of one period.
struct CropComponents {
    std::uint64_t components = 0;        ///< of the whole box
    std::vector<std::uint64_t> voxels;   ///< inside voxels of each of them, largest first
    std::uint64_t crop_components = 0;   ///< of the box's first period cell on its own
    /// Of that cell with opposite faces touching (the unbounded lattice); 0 when the box holds
    /// less than a period along some axis.
    std::uint64_t crop_components_periodic = 0;
};
/// The components (6-connected, value < 0) of @a field in the voxel box @a box (inclusive),
/// for a field whose inside voxels within the box repeat with @a period voxels along every
/// axis: a periodic lattice cut by a box, @a box being the voxels that the cut leaves inside.
/// Only the box's first period cell is evaluated; it and its versions cut short at the far box
/// faces are labelled voxel by voxel and joined across the faces between cells. Nothing shared:
/// the reference for shared_components() on lattices too large to label whole.
CropComponents plain_components_from_crop(const LeafField& field, const std::array<Coord3, 2>& box, int period);

}  // namespace vdbmesh
