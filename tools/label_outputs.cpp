// The outputs of `vdbmesh mesh --labels` (label_outputs.h).

#include "label_outputs.h"

#include <tbb/parallel_for.h>

#include <cstring>
#include <filesystem>

#include "gltf_document.h"
#include "label_input.h"
#include "vdbmesh/checked_output.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh::cli {

bool is_folder_output(const std::string& output) {
    std::error_code error;
    return (!output.empty() && output.back() == '/') || std::filesystem::is_directory(output, error);
}

std::string label_file_name(std::uint32_t value, const LabelTable& table, const std::string& extension) {
    const auto row = table.find(value);
    const std::string name = row != table.end() && !row->second.name.empty() ? "_" + file_safe(row->second.name) : "";
    return std::to_string(value) + name + "." + extension;
}

std::vector<std::string> write_label_folder(const LabelSurface& surface, const LabelTable& table, const std::string& output,
                                            const std::string& format, bool ascii) {
    const std::filesystem::path folder(output);
    std::error_code error;
    std::filesystem::create_directories(folder, error);
    if (error) throw Error(output + ": cannot make the folder (" + error.message() + ")");
    const std::vector<Mesh> meshes = label_meshes(surface);
    std::vector<std::string> written(meshes.size());
    for (std::size_t i = 0; i < meshes.size(); ++i) written[i] = (folder / label_file_name(surface.labels[i], table, format)).string();
    // Each file is written and synced to disk on its own (atomic_file.h): in parallel, the waits overlap.
    tbb::parallel_for(std::size_t(0), meshes.size(), [&](std::size_t i) { write_mesh(meshes[i], written[i], MeshWriteOptions{ascii, false}); });
    return written;
}

void write_label_ply(const LabelSurface& surface, const std::string& path) {
    CheckedOutput out(path);
    std::ostream& s = out.stream();
    s << "ply\nformat binary_little_endian 1.0\ncomment vdbmesh mesh --labels: each wall once, normal from label_inside to label_outside\n"
      << "element vertex " << surface.mesh.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "element face " << surface.mesh.triangles.size()
      << "\nproperty list uchar uint vertex_indices\nproperty ushort label_inside\nproperty ushort label_outside\nend_header\n";
    s.write(reinterpret_cast<const char*>(surface.mesh.vertices.data()), std::streamsize(surface.mesh.vertices.size() * 12));
    std::vector<char> face(1 + 12 + 4);  // x86 and the PLY are both little-endian
    face[0] = 3;
    for (std::size_t t = 0; t < surface.mesh.triangles.size(); ++t) {
        std::memcpy(face.data() + 1, surface.mesh.triangles[t].data(), 12);
        std::memcpy(face.data() + 13, surface.sides[t].data(), 4);
        s.write(face.data(), std::streamsize(face.size()));
    }
    out.commit();
}

std::array<double, 3> label_colour(std::uint32_t value, const LabelTable& table) {
    const auto row = table.find(value);
    if (row != table.end() && row->second.color) {
        const auto& c = *row->second.color;
        return {c[0] / 255.0, c[1] / 255.0, c[2] / 255.0};
    }
    // Golden-angle hues: well apart for neighbouring values.
    const double hue = std::fmod(value * 137.508, 360.0) / 60.0;
    const double x = 1 - std::abs(std::fmod(hue, 2.0) - 1);
    const double s = 0.65, v = 0.9, c = s * v, m = v - c;
    const int sector = int(hue);
    const std::array<double, 3> rgb = sector == 0 ? std::array<double, 3>{c, c * x, 0}
                                      : sector == 1 ? std::array<double, 3>{c * x, c, 0}
                                      : sector == 2 ? std::array<double, 3>{0, c, c * x}
                                      : sector == 3 ? std::array<double, 3>{0, c * x, c}
                                      : sector == 4 ? std::array<double, 3>{c * x, 0, c}
                                                    : std::array<double, 3>{c, 0, c * x};
    return {rgb[0] + m, rgb[1] + m, rgb[2] + m};
}

void write_label_gltf(const LabelSurface& surface, const LabelTable& table, const std::string& path) {
    GltfDocument document;
    using Json = GltfDocument::Json;
    Json nodes = Json::array();
    const std::vector<Mesh> meshes = label_meshes(surface);
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const std::uint32_t label = surface.labels[i];
        const Mesh& mesh = meshes[i];
        const auto row = table.find(label);
        const std::string name = row != table.end() ? row->second.name : "label " + std::to_string(label);
        const std::size_t material = document.add_material(name, label_colour(label, table));
        const std::size_t index = document.add_mesh(mesh, name, material);
        nodes.push_back(document.add_node({{"mesh", index}, {"name", name}, {"extras", {{"label", label}}}}));
    }
    document.write(path, nodes, "vdbmesh mesh --labels");
}

}  // namespace vdbmesh::cli
