// `vdbmesh mesh`: a .vdb grid or a scan (converted on the fly) to a triangle mesh file. It
// reports its figures on stderr, or with --json as one JSON object on stdout. With --verify the
// whole mesh is checked as `vdbmesh check` does (the meshers never run that check themselves);
// a defective mesh is reported, not written, and the exit status is 3. With --labels the input
// is a label map meshed per label (label_mesh_command.h).

#include <algorithm>
#include <cctype>
#include <chrono>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "common_options.h"
#include "label_mesh_command.h"
#include "load_grid.h"
#include "mesh_processing.h"
#include "report_json.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/read.h"

namespace vdbmesh::cli {

namespace {

const std::map<std::string, MeshMethod> kMethods = {
    {"dmc", MeshMethod::dmc}, {"mc", MeshMethod::mc}, {"openvdb", MeshMethod::openvdb}, {"dc", MeshMethod::dc}};
const std::map<std::string, Inside> kSides = {{"above", Inside::above}, {"below", Inside::below}};

struct MeshCommandOptions {
    std::vector<std::string> inputs;  ///< the input, then the further parts of a split raw scan
    std::string output;
    std::optional<double> iso;
    std::string method = "dc";
    std::optional<std::string> inside;  ///< default: above, below for a level set
    MeshOptions mesh;
    bool ascii = false;
    bool normals = false;
    bool json = false;
    bool verify = false;
    ReadFlags read;
    ProcessingOptions processing;
    CommonOptions common;
    LabelMeshRequest labels;  ///< used with --labels (its inputs, output, read and common options are copied in)
};

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

/// The grid to mesh, with options.mesh.iso set: a .vdb as stored, a scan converted (band 1).
openvdb::FloatGrid::Ptr load_mesh_grid(MeshCommandOptions& options, Progress& progress) {
    ConvertOptions convert;
    convert.band = conversion_band(options.processing);
    convert.progress = [&](double fraction) { progress(0.5 * fraction); };
    const GridInput loaded = load_grid(options.inputs, options.iso, options.read, "mesh", convert);
    options.mesh.iso = loaded.iso;
    options.mesh.inside = options.inside ? kSides.at(lowercase(*options.inside))
                                         : (loaded.level_set ? Inside::below : Inside::above);
    return loaded.grid;
}

/// What was made: the settings that made it, then its figures (the setting a method does not
/// use is null).
nlohmann::ordered_json figures_json(const MeshCommandOptions& options, const ProcessingReport& processing,
                                    const MeshResult& result, const std::optional<MeshAnalysis>& verified, double seconds) {
    const Mesh& mesh = result.mesh;
    const bool dmc = options.mesh.method == MeshMethod::dmc || options.mesh.method == MeshMethod::dc, openvdb = options.mesh.method == MeshMethod::openvdb;
    nlohmann::ordered_json j;
    j["output"] = options.output;
    j["method"] = lowercase(options.method);
    j["iso"] = options.mesh.iso;
    j["error"] = dmc ? nlohmann::ordered_json(options.mesh.error) : nlohmann::ordered_json(nullptr);
    j["adaptivity"] = openvdb ? nlohmann::ordered_json(options.mesh.adaptivity) : nlohmann::ordered_json(nullptr);
    j["processing"] = processing_json(options.processing, processing);
    j["triangles"] = mesh.triangles.size();
    j["vertices"] = mesh.vertices.size();
    j["seconds"] = seconds;
    // What the mesher did: its phases in the order run, DMC's safety-net rounds, fallbacks.
    j["phases"] = phases_json(result.report);
    j["refinement_rounds"] = result.report.refinement_rounds;
    j["fallbacks"] = result.report.fallbacks;
    j["verified"] = verified ? report_json(*verified) : nlohmann::ordered_json(nullptr);
    return j;
}

/// Exit status 0, or 3 when --verify found a defect (the mesh is then not written).
int run_mesh(MeshCommandOptions& options) {
    if (options.labels.label.labels) {
        LabelMeshRequest& request = options.labels;
        request.inputs = options.inputs, request.output = options.output, request.ascii = options.ascii;
        request.json = options.json, request.read = options.read, request.common = options.common;
        return run_label_mesh(request);
    }
    const std::string extension = lowercase_extension(options.output);
    if (extension != ".stl" && extension != ".ply" && extension != ".obj") {
        throw UsageError("-o: expected a .stl, .ply or .obj file, got \"" + options.output + "\"");
    }
    // Both words were checked (IsMember, any case).
    options.mesh.method = kMethods.at(lowercase(options.method));
    const ThreadLimit limit(options.common);
    const auto start = std::chrono::steady_clock::now();
    Progress progress("meshing", options.common.quiet);
    openvdb::FloatGrid::Ptr grid = load_mesh_grid(options, progress);
    ProcessingReport processing;
    process_grid(grid, options.mesh, options.processing, processing);
    options.mesh.progress = [&](double fraction) { progress(0.5 + 0.5 * fraction); };
    MeshResult result = mesh_grid(*grid, options.mesh);
    result.mesh = process_mesh(std::move(result.mesh), options.processing, processing);
    const Mesh& mesh = result.mesh;
    if (mesh.triangles.empty())
        throw no_surface_error(options.inputs.front(), *grid, {options.mesh.iso, options.mesh.iso}, options.output);
    std::optional<MeshAnalysis> verified;
    if (options.verify) verified = analyze_mesh(mesh);
    const bool defective = verified && !verified->is_clean();
    if (!defective) write_mesh(mesh, options.output, MeshWriteOptions{options.ascii, options.normals});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (options.json) {
        std::cout << detail::json_text(figures_json(options, processing, result, verified, seconds)) << "\n";
    } else if (!options.common.quiet || defective) {
        for (const std::string& fallback : result.report.fallbacks) std::cerr << "vdbmesh mesh: fell back to " << fallback << "\n";
        if (defective) {
            std::cerr << "vdbmesh mesh: --verify: the mesh is not clean (" << verified->self_intersecting_pairs
                      << " self-intersecting pairs, " << verified->boundary_edges << " boundary edges, "
                      << verified->nonmanifold_edges << " non-manifold edges, " << verified->nonmanifold_vertices
                      << " non-manifold vertices, " << verified->misoriented_edges << " misoriented edges, "
                      << verified->degenerate_faces << " degenerate faces); " << options.output << " not written\n";
        } else {
            std::cerr << "vdbmesh mesh: " << mesh.triangles.size() << " triangles, " << mesh.vertices.size()
                      << " vertices, " << seconds << " s -> " << options.output << (verified ? " (verified clean)" : "") << "\n";
        }
    }
    return defective ? 3 : 0;
}

}  // namespace

void add_mesh_command(CLI::App& command, CommandResult& result) {
    auto options = std::make_shared<MeshCommandOptions>();
    command.add_option("INPUT", options->inputs, "A .vdb grid or a scan (extra files: the parts of a split raw scan)")
        ->required();
    command.add_option("-o,--output", options->output, "Mesh file: .stl, .ply or .obj (with --labels: DIR/, .ply or .glb/.gltf)")->required();
    command.add_option("--iso", options->iso, "Isovalue (default for a .vdb: the one stored by convert)");
    command.add_option("--method", options->method,
                       "Mesher: dc (intersection-free Dual Contouring, the default), dmc (Dual Marching Cubes), mc, openvdb (volumeToMesh)")
        ->check(CLI::IsMember(kMethods, CLI::ignore_case))
        ->capture_default_str();
    command.add_option("--error", options->mesh.error, "dc, dmc: tolerated error in voxels (0: no simplification; dc: the dual mesh, a vertex per cell; dmc: Marching Cubes)")
        ->check(kFiniteNonNegative)
        ->capture_default_str();
    command.add_option("--adaptivity", options->mesh.adaptivity, "openvdb: volumeToMesh adaptivity in [0, 1]")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    command.add_option("--inside", options->inside,
                       "Which side of the isovalue is the object: above|below (default: above; below for a level set)")
        ->check(CLI::IsMember(kSides, CLI::ignore_case));
    command.add_flag("--open-boundary", options->mesh.open_boundary,
                     "Leave the surface open where it meets the edge of the scan");
    command.add_flag("--ascii", options->ascii, "ASCII STL or PLY instead of binary");
    command.add_flag("--normals", options->normals, "Per-vertex normals (PLY, OBJ)");
    command.add_flag("--json", options->json, "Print the figures as one JSON object on stdout");
    command.add_flag("--verify", options->verify,
                     "Check the whole mesh as `vdbmesh check` does; a defect: nothing written, exit status 3");
    add_read_flags(command, options->read);
    add_processing_options(command, options->processing);
    add_common_options(command, options->common);
    add_label_flags(command, options->labels.label, "Mesh a label map: all, or a list like 3,5,10-12; one closed mesh per label, walls shared");
    command.add_option("--format", options->labels.format, "--labels into a folder: the files' format")
        ->check(CLI::IsMember({"stl", "ply", "obj"}))
        ->capture_default_str();
    command.add_option("--smooth-iterations", options->labels.smooth_iterations, "--labels: constrained smoothing passes (0: voxel faces)")
        ->check(CLI::Range(0, 1000))
        ->capture_default_str();
    command.callback([options, &result] {
        result.status = run_mesh(*options);
    });
}

}  // namespace vdbmesh::cli
