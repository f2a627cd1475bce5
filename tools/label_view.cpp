// The label map of `vdbmesh view --labels` (label_view.h).

#include "label_view.h"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "label_outputs.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/labels.h"

namespace vdbmesh::cli {

ViewSource label_view_source(const std::vector<std::string>& inputs, const ReadFlags& read, const LabelFlags& flags) {
    const LabelInput input = load_label_input(inputs, read, flags);
    LabelMeshOptions options;
    options.labels = parse_label_list(*flags.labels);
    const LabelSurface surface = mesh_labels(input.volume, options);
    if (surface.labels.empty() || surface.mesh.triangles.empty())
        throw Error(inputs.front() + ": none of the labels asked for is in the map");
    std::vector<Mesh> meshes = label_meshes(surface);
    auto all = std::make_shared<Mesh>();
    ViewSource source;
    source.name = std::filesystem::path(inputs.front()).filename().string();
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        ViewLabel label;
        label.value = surface.labels[i];
        const auto row = input.table.find(label.value);
        label.name = row != input.table.end() && !row->second.name.empty() ? row->second.name : "label " + std::to_string(label.value);
        label.colour = label_colour(label.value, input.table);
        label.first_triangle = all->triangles.size();
        label.triangles = meshes[i].triangles.size();
        label.first_vertex = all->vertices.size();
        label.vertices = meshes[i].vertices.size();
        const auto offset = std::uint32_t(label.first_vertex);
        for (const auto& t : meshes[i].triangles) all->triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
        all->vertices.insert(all->vertices.end(), meshes[i].vertices.begin(), meshes[i].vertices.end());
        meshes[i] = Mesh();
        source.labels.push_back(std::move(label));
    }
    source.mesh = std::move(all);
    return source;
}

std::string label_figures(const Mesh& mesh, const std::vector<ViewLabel>& labels) {
    nlohmann::ordered_json j;
    std::size_t nonmanifold_edges = 0, nonmanifold_vertices = 0, self_intersecting_pairs = 0, components = 0;
    double area = 0, volume = 0;
    bool closed = true;
    for (const ViewLabel& label : labels) {
        Mesh one;
        one.vertices.assign(mesh.vertices.begin() + std::ptrdiff_t(label.first_vertex),
                            mesh.vertices.begin() + std::ptrdiff_t(label.first_vertex + label.vertices));
        for (std::size_t t = label.first_triangle; t < label.first_triangle + label.triangles; ++t) {
            const auto& tri = mesh.triangles[t];
            const auto offset = std::uint32_t(label.first_vertex);
            one.triangles.push_back({tri[0] - offset, tri[1] - offset, tri[2] - offset});
        }
        const MeshAnalysis a = analyze_mesh(one);
        nonmanifold_edges += a.nonmanifold_edges;
        nonmanifold_vertices += a.nonmanifold_vertices;
        self_intersecting_pairs += a.self_intersecting_pairs;
        components += a.components;
        area += a.area;
        volume += a.volume;
        closed = closed && a.closed;
    }
    j["labels"] = labels.size();
    j["closed"] = closed;
    j["nonmanifold_edges"] = nonmanifold_edges;
    j["nonmanifold_vertices"] = nonmanifold_vertices;
    j["self_intersecting_pairs"] = self_intersecting_pairs;
    j["components"] = components;
    j["area"] = area;
    j["volume"] = volume;
    return detail::json_text(j);
}

}  // namespace vdbmesh::cli
