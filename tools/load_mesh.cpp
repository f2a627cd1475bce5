// The input of the mesh-consuming subcommands: a mesh file or a scan meshed in memory.

#include "load_mesh.h"

#include <map>

#include "load_grid.h"
#include "option_checks.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid_filter.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh::cli {

namespace {
const std::map<std::string, Inside> kSides = {{"above", Inside::above}, {"below", Inside::below}};
}

void add_mesh_input_options(CLI::App& command, MeshInputOptions& options) {
    options.grid_only = {
        command.add_option("--iso", options.iso, "Isovalue for a scan or .vdb input (default for a .vdb: the stored one)"),
        command.add_option("--inside", options.inside, "Scan or .vdb input: which side of the isovalue is the object: above|below")
            ->transform(CLI::CheckedTransformer(kSides, CLI::ignore_case)),
        command.add_flag("--refine", options.refine,
                         "Scan or .vdb input: move the vertices onto the isosurface of the triquadratic interpolant "
                         "(sub-voxel accuracy on smooth solids)"),
    };
    add_read_flags(command, options.read);
}

Mesh load_mesh(const std::vector<std::string>& inputs, const MeshInputOptions& options, const std::string& purpose) {
    if (is_mesh_file(inputs.front())) {
        if (inputs.size() > 1) throw UsageError("a mesh input takes no further input files");
        for (const CLI::Option* option : options.grid_only)
            refuse_unless(option, false, "for a scan or .vdb input, got the mesh " + inputs.front());
        options.read.refuse_for("the mesh " + inputs.front());
        return read_mesh(inputs.front());
    }
    ConvertOptions convert;
    convert.band = 1;
    const GridInput loaded = load_grid(inputs, options.iso, options.read, purpose, convert, options.iso_option, options.inside);
    MeshOptions mesh;
    mesh.iso = loaded.iso;
    mesh.inside = loaded.inside;
    Mesh result = mesh_grid(*loaded.grid, mesh).mesh;
    if (result.triangles.empty()) throw no_surface_error(inputs.front(), *loaded.grid, {loaded.iso, loaded.iso}, "");
    if (options.refine) refine_to_isosurface(result, *loaded.grid, loaded.iso);
    return result;
}

}  // namespace vdbmesh::cli
