#pragma once
// The input of the mesh-consuming subcommands (measure, section): a mesh file as stored, or a
// scan or .vdb meshed in memory (Dual Marching Cubes at error 0) without writing a file.

#include <optional>
#include <string>
#include <vector>

#include "common_options.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::cli {

/// How a scan or grid input is meshed.
struct MeshInputOptions {
    std::optional<double> iso;
    std::string iso_option = "--iso";  ///< the option that gives iso, for messages
    Inside inside = Inside::above;
    bool refine = false;  ///< vertices onto the triquadratic isosurface (refine_to_isosurface)
    ReadFlags read;
    /// The options that mean something only for a scan or .vdb input (--iso, --inside, --refine,
    /// or lattice's --clip-iso and --clip-inside): given with a mesh file, they are refused.
    std::vector<const CLI::Option*> grid_only;
};

/// --iso, --inside, --refine and the raw-scan flags.
void add_mesh_input_options(CLI::App& command, MeshInputOptions& options);

/// inputs.front() read as a mesh when is_mesh_file(), else loaded as a grid (load_grid) and
/// meshed (and refined with --refine); @a purpose ("measure") completes the message when --iso
/// is missing.
Mesh load_mesh(const std::vector<std::string>& inputs, const MeshInputOptions& options, const std::string& purpose);

}  // namespace vdbmesh::cli
