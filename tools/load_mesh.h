#pragma once
// The input of the mesh-consuming subcommands (measure, section): a mesh file as stored, or a
// scan or .vdb meshed in memory (Dual Marching Cubes at --error, 0 unless given) without writing
// a file; with --memory, a scan or .vdb meshed by bricks and handed on as a stream.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common_options.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::cli {

/// How a scan or grid input is meshed.
struct MeshInputOptions {
    std::optional<double> iso;
    std::string iso_option = "--iso";  ///< the option that gives iso, for messages
    Inside inside = Inside::above;
    double error = 0;     ///< the dc mesher's tolerated error in voxels (0: Marching Cubes)
    bool refine = false;  ///< vertices onto the triquadratic isosurface (refine_to_isosurface)
    ReadFlags read;
    /// The options that mean something only for a scan or .vdb input (--iso, --inside, --refine,
    /// or lattice's --clip-iso and --clip-inside): given with a mesh file, they are refused.
    std::vector<const CLI::Option*> grid_only;
};

/// --iso, --inside, --error, --refine and the raw-scan flags.
void add_mesh_input_options(CLI::App& command, MeshInputOptions& options);

/// True when inputs.front() is a mesh file (is_mesh_file()); then refuses further inputs and the
/// options meant for a scan or .vdb (usage errors).
bool is_mesh_input(const std::vector<std::string>& inputs, const MeshInputOptions& options);

/// inputs.front() read as a mesh when is_mesh_file(), else loaded as a grid (load_grid) and
/// meshed (and refined with --refine); @a purpose ("measure") completes the message when --iso
/// is missing.
Mesh load_mesh(const std::vector<std::string>& inputs, const MeshInputOptions& options, const std::string& purpose);

/// With --memory @a memory_bytes and a scan or .vdb input: what the stream of its bricked mesh
/// may hold: the program (kProgramBytes) and half the rest (the stream is fed while the mesher
/// reads its spill back, which holds about as much: the k = 3 bunny measured with the whole
/// limit each peaked at 1.48 GiB for --memory 1G). @throw UsageError, before any work, when
/// that share is under @a least_stream_bytes (naming the smallest limit that could work).
std::uint64_t grid_stream_share(std::uint64_t memory_bytes, std::uint64_t least_stream_bytes, const std::string& verb,
                                const std::string& input);

/// With --memory and a scan or .vdb input (not is_mesh_file()): the surface meshed by bricks
/// within @a memory_bytes (the .vdb or scan read by region, as `mesh --memory` reads it) and
/// handed to @a visitor as a file of it would be read: announced(), the vertices, the
/// triangles. The same mesh as load_mesh() at the same --error.
/// @a visitor plans for grid_stream_share() of @a memory_bytes; the mesher, for all of it.
/// @throw UsageError for --error 0 or --refine (the whole mesh) and a limit under one brick.
void stream_grid_mesh(const std::vector<std::string>& inputs, const MeshInputOptions& options, const std::string& purpose,
                      std::uint64_t memory_bytes, MeshRecordVisitor& visitor);

}  // namespace vdbmesh::cli
