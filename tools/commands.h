#pragma once
// The registry of subcommands: one line each, from which `vdbmesh --help` is generated.
// Each subcommand lives in tools/cmd_<name>.cpp and exposes add_<name>_command().

#include <CLI/CLI.hpp>

namespace vdbmesh::cli {

/// Where a subcommand's callback stores its exit status.
struct CommandResult {
    int status = 0;
};

using AddCommand = void (*)(CLI::App& command, CommandResult& result);

struct CommandEntry {
    const char* name;
    const char* summary;
    AddCommand add;
};

void add_info_command(CLI::App& command, CommandResult& result);
void add_convert_command(CLI::App& command, CommandResult& result);
void add_phantom_command(CLI::App& command, CommandResult& result);
void add_mesh_command(CLI::App& command, CommandResult& result);
void add_check_command(CLI::App& command, CommandResult& result);
void add_compare_command(CLI::App& command, CommandResult& result);
void add_view_command(CLI::App& command, CommandResult& result);
void add_measure_command(CLI::App& command, CommandResult& result);
void add_section_command(CLI::App& command, CommandResult& result);
void add_lattice_command(CLI::App& command, CommandResult& result);
void add_process_command(CLI::App& command, CommandResult& result);
void add_reconstruct_command(CLI::App& command, CommandResult& result);
void add_similarity_command(CLI::App& command, CommandResult& result);
void add_classify_command(CLI::App& command, CommandResult& result);

/// All subcommands, in the order --help lists them.
inline constexpr CommandEntry kCommands[] = {
    {"info", "Describe a scan or .vdb file and suggest an isovalue", add_info_command},
    {"convert", "Stream a scan into a sparse OpenVDB grid (.vdb)", add_convert_command},
    {"phantom", "Write a synthetic test volume (sphere, cube, torus ...) in any format we read", add_phantom_command},
    {"mesh", "Mesh a .vdb grid or a scan at an isovalue into STL, PLY or OBJ (DC, MC or volumeToMesh)", add_mesh_command},
    {"check", "Validate a mesh (closed, manifold, oriented, self-intersections) and measure it", add_check_command},
    {"measure", "Area, volume, centroid, inertia, principal axes, genus and components of a mesh or of a scan's surface", add_measure_command},
    {"section", "Cut a closed mesh (or a scan's surface) by planes: nested loops, area, perimeter, moments, SVG", add_section_command},
    {"reconstruct", "Points (.xyz, .ply, a .conf range-scan set) to a closed surface or a signed field (.vdb) by partition-of-unity RBF", add_reconstruct_command},
    {"similarity", "How alike two solids given by points are, and the scale, rotation and translation between them", add_similarity_command},
    {"classify", "The class (NAME=reference points) whose solid is most like a sample's", add_classify_command},
    {"compare", "Mesh one grid with DC, MC and volumeToMesh; time them, validate them, measure them against the true surface", add_compare_command},
    {"lattice", "Build a periodic lattice (gyroid, Schwarz P, diamond, bcc struts) as a shared tree; write .vdb, a mesh or instanced glTF, or --measure it", add_lattice_command},
    {"process", "Process steps on a level set in order (--deposit D, --etch z:D down to a --stop-layer), on the shared tree", add_process_command},
    {"view", "Show a scan (re-meshed live as the isovalue moves) or a mesh in the browser", add_view_command},
};

}  // namespace vdbmesh::cli
