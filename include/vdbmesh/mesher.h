#pragma once
/// @file mesher.h
/// @brief Meshing a sparse grid: intersection-free Dual Contouring on the VDB tree, Marching
/// Cubes, or OpenVDB's volumeToMesh, all returning the same indexed, welded, oriented Mesh, with a
/// report of what the mesher did. OpenVDB-free: the grid is only declared (openvdb_fwd.h);
/// grid.h makes and reads grids.

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/openvdb_fwd.h"
#include "vdbmesh/ranks.h"

namespace vdbmesh {


enum class MeshMethod {
    mc,       ///< Marching Cubes on the samples, vertices welded by grid edge
    openvdb,  ///< openvdb::tools::volumeToMesh, quads split along the shorter diagonal
    dc,       ///< intersection-free Dual Contouring on the leaf octrees (Ju and Udeshi 2006), Marching
              ///< Cubes in unit cells, adaptive by --error
    dual,     ///< experimental: a vertex per Marching Cubes polygon of each cell on the trilinear
              ///< isosurface, a quad per crossed grid edge, proved free of crossings (docs/dmc.md,
              ///< "Error 0: the dual mesh"); whole grids only
};

/// Which side of the isovalue is the object.
enum class Inside {
    above,  ///< values above the isovalue (dense material in CT)
    below,  ///< values below it (level sets, --inside below)
};

struct MeshOptions {
    MeshMethod method = MeshMethod::dc;  ///< the default: clean by construction at any error
    double iso = 0.0;           ///< isovalue, in the grid's value units
    double error = 0.0;         ///< dc: error tolerance in voxels (0: no merging, equals MC)
    double adaptivity = 0.0;    ///< openvdb: volumeToMesh adaptivity in [0, 1]
    Inside inside = Inside::above;
    bool open_boundary = false; ///< leave the surface open where it meets the scan's box
    /// dc, error > 0: vertices on sharp edges and corners, up to a voxel beyond the error from
    /// the trilinear isosurface there; elsewhere the same mesh (docs/dmc.md, "Sharp features")
    bool sharp = false;
    std::function<void(double)> progress;  ///< fraction done (0..1), may be empty
};

/// One step of a mesher and the wall time it took.
struct MeshPhase {
    std::string name;  ///< "mesh" (MC, volumeToMesh); DC: "octree", "coarse", "split", "contour", "weld"
    double seconds = 0;
};

/// A brick's size across (docs/dmc.md, "Bricks"): nodes (kNodeVoxels each) in x and in y; a
/// brick is one node high. {0, 0}: not given.
struct BrickShape {
    int nodes_x = 0;
    int nodes_y = 0;
    bool given() const { return nodes_x != 0 || nodes_y != 0; }
};

/// What mesh_grid() did: the settings it ran with, where the time went, and anything it
/// did instead of what was asked.
struct MeshReport {
    MeshMethod method = MeshMethod::dc;
    double iso = 0;
    double error = 0;
    double adaptivity = 0;
    Inside inside = Inside::above;
    bool open_boundary = false;
    std::vector<MeshPhase> phases;       ///< in the order run
    std::vector<std::string> fallbacks;  ///< anything the mesher fell back to, in words; empty when none
    /// How mesh_bricks() cut the grid: a brick's nodes across and how many bricks (docs/dmc.md,
    /// "Bricks"); all 0 when the grid was meshed whole.
    BrickShape brick_shape;
    std::uint64_t bricks = 0;
    std::uint64_t estimated_peak_bytes = 0;  ///< brick_peak_bytes() of that cut
    double total_seconds() const;        ///< the sum of the phases
};

/// A mesh and how it was made.
struct MeshResult {
    Mesh mesh;
    MeshReport report;
};

/// Meshes @a grid at options.iso. The result is in world coordinates (the grid's
/// transform), triangles counter-clockwise seen from outside the object. Unless
/// open_boundary, the surface is closed where the object meets the edge of the scanned
/// box (kMetaScanMin/Max metadata; outside it counts as outside the object). The same
/// grid and options give the same mesh, whatever the thread count.
/// MeshMethod::openvdb meshes the grid's values as they are (no scan-box closing).
/// @throw UsageError for a non-finite iso, error < 0, adaptivity outside [0, 1], or
/// open_boundary with MeshMethod::openvdb.
MeshResult mesh_grid(const openvdb::FloatGrid& grid, const MeshOptions& options);

/// How mesh_bricks() cuts the grid (docs/dmc.md, "Bricks").
struct BrickOptions {
    /// The bricks' size across. The bricks of a column (the same x, y) are meshed bottom to top
    /// with a ring of one node round the column. Planned when not given: one column holding
    /// the whole grid, unless memory_bytes is set.
    BrickShape shape;
    /// With the shape not given: of the shapes whose estimated peak (brick_peak_bytes()) fits,
    /// the one that builds the least octree twice (docs/dmc.md, "Bricks").
    std::uint64_t memory_bytes = 0;
    /// A run over several processes (ranks.h), for mesh_bricks_to_stream(): this one, @a rank
    /// of @a ranks, meshes the bricks bricks_to_ranks() gives it; rank 0 receives every other
    /// rank's part with @a gather (a collective call, as ranks.h's stream_to_rank0(): the parts
    /// streamed to rank 0 in rank order) and alone sends the mesh to its sink, the same vertices
    /// and triangles in the same order as one process (unless the ranks write together:
    /// collectives below). One rank: nothing is gathered.
    int rank = 0;
    int ranks = 1;
    std::function<void(const RankPart& mine, PartReceiver& receiver)> gather;
    /// Ranks that can talk (ranks.h's ranks_collectives()) and a sink with ranges(): every rank
    /// resolves and writes its own nodes' part of the file instead (docs/scale.md, "Assembly on
    /// every rank"); the same bytes.
    std::optional<RankCollectives> collectives;
};

class MeshRangeSink;

/// Where mesh_bricks_to_stream() sends the mesh, in mesh_bricks()'s order: the counts, every
/// vertex, then every triangle with its corners' positions (what a MeshStreamWriter takes).
class MeshStreamSink {
public:
    virtual ~MeshStreamSink() = default;
    virtual void begin(std::uint64_t vertex_count, std::uint64_t triangle_count) = 0;
    virtual void vertex(const std::array<float, 3>& position) = 0;
    virtual void triangle(const std::array<std::uint32_t, 3>& triangle, const std::array<std::array<float, 3>, 3>& corners) = 0;
    /// False when triangle() ignores its corners (they may then be zeros): a file of vertex
    /// numbers (PLY, OBJ) spares the spill a third of its bytes.
    virtual bool needs_corners() const { return true; }
    /// The sink's form for ranks that write the file together (BrickOptions::collectives), if
    /// it has one; otherwise rank 0 receives the others' parts and alone sends the mesh here.
    virtual MeshRangeSink* ranges() { return nullptr; }
};

/// A file that ranks write together (BrickOptions::collectives; docs/scale.md, "Assembly on
/// every rank"): each rank formats its own nodes' vertices and triangles and writes them at
/// their places in one file every rank opens (a shared file system); rank 0 makes it, writes
/// the header and footer, and commits it once every rank has written.
class MeshRangeSink {
public:
    virtual ~MeshRangeSink() = default;
    /// The bytes before the first vertex, on every rank, for the whole mesh's counts.
    /// @throw as MeshStreamSink::begin() (every rank alike).
    virtual std::string header(std::uint64_t vertex_count, std::uint64_t triangle_count) = 0;
    /// The bytes after the last triangle.
    virtual std::string footer() const = 0;
    /// Appends the bytes of @a positions, of @a triangles (with their corners when
    /// MeshStreamSink::needs_corners(), else @a corners may be empty) to @a out.
    virtual void vertices(const std::vector<std::array<float, 3>>& positions, std::string& out) const = 0;
    virtual void triangles(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                           const std::vector<std::array<std::array<float, 3>, 3>>& corners, std::string& out) const = 0;
    /// Rank 0 (@a made empty): makes the temporary file and returns its path; the other ranks
    /// open rank 0's path, @a made.
    virtual std::string open(const std::string& made) = 0;
    /// Writes @a count bytes at @a offset of the file.
    virtual void write_at(std::uint64_t offset, const char* bytes, std::size_t count) = 0;
    /// Closes the file; on rank 0 with @a commit (every rank wrote its part), syncs and renames
    /// it into place, and without, removes it.
    virtual void close(bool commit) = 0;
};

/// mesh_bricks() without holding the mesh: each brick's vertices and triangles go to a spill
/// (an unlinked temporary file) as soon as it is meshed, and after the last brick the spill is
/// read back node by node into @a sink (docs/dmc.md, "Bricks"). The same vertices and triangles
/// in the same order as mesh_bricks(); MeshMethod::dc and mc only. Returns the
/// report (its mesh went to the sink). Over several ranks (BrickOptions::ranks), only rank 0's
/// sink receives anything.
/// @throw UsageError as mesh_bricks(); Error when the spill cannot be written.
MeshReport mesh_bricks_to_stream(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks,
                                 MeshStreamSink& sink);

/// The estimated peak of meshing @a source in columns of bricks of @a shape (the largest over
/// its bricks): three node layers of a column and its ring of nodes read (docs/dmc.md,
/// "Bricks"), and the mesher's work on them.
std::uint64_t brick_peak_bytes(const GridRegionSource& source, const BrickShape& shape);

/// The mesh mesh_grid() makes of the grid @a source holds, read brick by brick: the same
/// bytes for any brick size and thread count. MeshMethod::dc and mc mesh by bricks (at error 0
/// and with mc, Marching Cubes brick by brick); with no shape and no memory limit any method meshes
/// the whole grid, read as one region.
/// @throw UsageError as mesh_grid(), and for bricks with MeshMethod::openvdb, or
/// a shape outside [1, 4096] nodes across (or one side 0); before any work, when memory_bytes is below
/// brick_peak_bytes() of a brick of one node (naming the smallest limit that works).
MeshResult mesh_bricks(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks);

}  // namespace vdbmesh
