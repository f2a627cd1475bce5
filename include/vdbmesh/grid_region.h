#pragma once
/// @file grid_region.h
/// @brief A grid read by region: the interface between the bricked mesher (and the viewer's
/// server) and where the samples come from (a .vdb read with delayed loading, a scan streamed
/// in z-bands, or a grid already in memory). OpenVDB-free: grids are only declared.
///
/// The unit of every region is the **node**: a 128^3-voxel level-1 internal node of OpenVDB's
/// standard float tree (origin a multiple of 128 on each axis). A brick is a box of whole
/// nodes; the bricked mesher asks for a brick's box widened by its halo.

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "vdbmesh/openvdb_fwd.h"

namespace vdbmesh {

/// Voxels per node edge (OpenVDB's level-1 internal node of the standard FloatTree).
inline constexpr std::int32_t kNodeVoxels = 128;

/// A box of voxels in the grid's index space: min inclusive, max exclusive.
struct IndexBox {
    std::array<std::int32_t, 3> min{};
    std::array<std::int32_t, 3> max{};
};

/// A node that holds active voxels or active tiles, with how many it holds (from the tree's
/// topology alone, without reading voxel values): the weight bricks are balanced by.
struct NodeWeight {
    std::array<std::int32_t, 3> origin{};  ///< multiple of kNodeVoxels on each axis
    std::uint64_t active_voxels = 0;
};

/// The active voxels of one 8^3 leaf: its value mask, bit i of the 512 being voxel
/// origin + (x, y, z) with i = x * 64 + y * 8 + z, as OpenVDB orders a leaf (on[x] holds the
/// row of x, bit y * 8 + z).
struct LeafMask {
    std::array<std::int32_t, 3> origin{};  ///< multiple of 8 on each axis
    std::array<std::uint64_t, 8> on{};
};

/// Where a region of one float grid comes from. Implementations are read-only after opening;
/// read() may be called from several threads at once.
class GridRegionSource {
public:
    virtual ~GridRegionSource() = default;

    /// The grid's description without its voxels: transform, grid class, background and
    /// metadata (vdbmesh_isovalue, vdbmesh_scan_min/max ...), with an empty tree.
    virtual std::shared_ptr<const openvdb::FloatGrid> description() const = 0;

    /// Every node holding an active voxel or tile, in z-major order (origin z, then y, then x,
    /// ascending): the order bricks are visited in, so a scan can be streamed front to back.
    virtual std::vector<NodeWeight> nodes() const = 0;

    /// A grid whose every voxel inside @a box has the value and active state it has in the whole
    /// grid. Outside the box it holds whatever was cheapest to read (at least the background).
    virtual std::shared_ptr<openvdb::FloatGrid> read(const IndexBox& box) const = 0;

    /// An upper estimate of the bytes read(box) holds while its grid lives (for --memory plans).
    virtual std::uint64_t estimated_bytes(const IndexBox& box) const = 0;

    /// An upper estimate of the bytes of the grid read(box) returns alone, without what the
    /// source holds while reading (a scan's read buffer): what a reader keeping that grid after
    /// the read holds.
    virtual std::uint64_t grid_bytes(const IndexBox& box) const { return estimated_bytes(box); }

    /// The bytes opening the source held at most and no longer holds (a scan's survey: the
    /// converter's slice windows across the whole scan): a peak no plan of reads can go below.
    virtual std::uint64_t opening_bytes() const { return 0; }

    /// The leaves that hold an active voxel inside @a box, each with its mask cleared outside
    /// the box, in z-major order of their origins (as nodes()): where the active band round a
    /// scan's surface lies, for a picture of it before any value is read (the viewer's topology
    /// preview). Active tiles are not listed: a tile holds one value, so the isosurface does
    /// not pass through it (vdbmesh's converted grids have none); a caller wanting them has
    /// nodes(). This default reads the region (read(box)); a .vdb's source answers from the
    /// topology it read at opening, without loading a leaf's values.
    virtual std::vector<LeafMask> active_leaves(const IndexBox& box) const;
};

/// Adds to @a into what @a region holds: its tiles copied at their own level, its leaves moved
/// (@a region is left without leaves). For parts of one grid read by region with boxes that
/// share no leaf, so that the tiles both hold are the same tile (the bricked mesher's wavefront
/// assembles its layers so).
void absorb_region(openvdb::FloatGrid& into, openvdb::FloatGrid& region);

/// Frees every 128^3 node of @a grid lying wholly below z = @a z (its leaves with it); the grid
/// is unchanged at and above @a z.
void drop_nodes_below(openvdb::FloatGrid& grid, std::int32_t z);

/// A grid already in memory seen as regions (read() copies the part of the tree that meets
/// the box). For tests, and for the commands that built their grid in memory.
std::unique_ptr<GridRegionSource> grid_regions_in_memory(std::shared_ptr<const openvdb::FloatGrid> grid);

/// The first float grid of a .vdb file by region. Opening reads the headers and the tree's
/// topology (OpenVDB's delayed loading: the file is mapped, leaf buffers stay on disk); read()
/// loads only the leaves that meet its box. The file is untrusted: every decoding of it runs
/// first, or only, in a forked child whose crash becomes a FormatError naming the file (see
/// src/grid/vdb_probe.h). The file must not change while the source lives (replacing it by a
/// rename is safe). The grid's vdbmesh_checksum covers the whole tree and is not checked here
/// (read_vdb() checks it). Throws FormatError as read_vdb() does.
std::unique_ptr<GridRegionSource> open_vdb_regions(const std::filesystem::path& path);

}  // namespace vdbmesh
