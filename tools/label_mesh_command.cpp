// `vdbmesh mesh --labels`: read the label map and its names, mesh the labels asked for with
// shared walls (labels.h), write a folder, a PLY with label pairs or a glTF, report the figures.

#include "label_mesh_command.h"

#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>

#include "label_outputs.h"
#include "load_grid.h"  // lowercase_extension
#include "vdbmesh/error.h"
#include "vdbmesh/json_text.h"

namespace vdbmesh::cli {
namespace {

enum class LabelOutputKind { folder, ply, gltf };

LabelOutputKind output_kind(const std::string& output) {
    if (is_folder_output(output)) return LabelOutputKind::folder;
    const std::string extension = lowercase_extension(output);
    if (extension == ".ply") return LabelOutputKind::ply;
    if (extension == ".glb" || extension == ".gltf") return LabelOutputKind::gltf;
    throw UsageError("-o: with --labels expected a folder (DIR/: one file per label), a .ply (one mesh, each face's label pair) or a .glb/.gltf (one mesh per label), got \"" +
                     output + "\"");
}

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// @a phases: the mesher's, between reading the map and writing the outputs.
nlohmann::ordered_json figures_json(const LabelMeshRequest& request, const LabelSurface& surface,
                                    const std::vector<std::pair<std::string, double>>& phases, const std::vector<std::string>& files,
                                    double seconds) {
    nlohmann::ordered_json j;
    j["output"] = request.output;
    j["method"] = "labels";
    j["labels"] = surface.labels;
    j["triangles"] = surface.mesh.triangles.size();
    j["vertices"] = surface.mesh.vertices.size();
    j["relabelled_voxels"] = surface.relabelled_voxels;
    j["vertices_held_back"] = surface.vertices_held_back;
    j["hold_back_rounds"] = surface.hold_back_rounds;
    j["smooth_iterations"] = request.smooth_iterations;
    j["seconds"] = seconds;
    j["phases"] = nlohmann::ordered_json::array();
    for (const auto& [name, s] : phases) j["phases"].push_back({{"name", name}, {"seconds", s}});
    j["files"] = files;
    return j;
}

}  // namespace

int run_label_mesh(const LabelMeshRequest& request) {
    const LabelOutputKind kind = output_kind(request.output);
    LabelMeshOptions options;
    options.labels = parse_label_list(request.label.labels->empty() ? "all" : *request.label.labels);
    options.smoothing_iterations = request.smooth_iterations;
    const ThreadLimit limit(request.common);
    const auto start = Clock::now();
    Progress progress("meshing labels", request.common.quiet);
    const LabelInput input = load_label_input(request.inputs, request.read, request.label);
    std::vector<std::pair<std::string, double>> phases{{"read", seconds_since(start)}};
    const LabelSurface surface = mesh_labels(input.volume, options, [&](double f) { progress(f); });
    phases.insert(phases.end(), surface.phases.begin(), surface.phases.end());
    const auto writing = Clock::now();
    if (surface.labels.empty() || surface.mesh.triangles.empty())
        throw Error(request.inputs.front() + ": none of the labels asked for is in the map; " + request.output + " not written");
    std::vector<std::string> files;
    if (kind == LabelOutputKind::folder) files = write_label_folder(surface, input.table, request.output, request.format, request.ascii);
    else if (kind == LabelOutputKind::ply) write_label_ply(surface, request.output), files = {request.output};
    else write_label_gltf(surface, input.table, request.output), files = {request.output};
    phases.emplace_back("write", seconds_since(writing));
    const double seconds = seconds_since(start);
    if (request.json) std::cout << detail::json_text(figures_json(request, surface, phases, files, seconds)) << "\n";
    else if (!request.common.quiet)
        std::cerr << "vdbmesh mesh: " << surface.labels.size() << " labels, " << surface.mesh.triangles.size() << " triangles (each wall once), "
                  << surface.relabelled_voxels << " voxels relabelled, " << seconds << " s -> " << request.output << "\n";
    return 0;
}

}  // namespace vdbmesh::cli
