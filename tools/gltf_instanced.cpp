#include "gltf_instanced.h"

#include "gltf_document.h"

namespace vdbmesh::cli {

void write_instanced_gltf(const InstancedMesh& mesh, const std::string& path) {
    GltfDocument document;
    GltfDocument::Json scene_nodes = GltfDocument::Json::array();
    // Instances grouped by part, in part order.
    std::vector<std::vector<std::array<float, 3>>> translations(mesh.parts.size());
    for (const auto& i : mesh.instances) {
        translations[i.part].push_back({float(i.translation[0]), float(i.translation[1]), float(i.translation[2])});
    }
    for (std::size_t p = 0; p < mesh.parts.size(); ++p) {
        const std::size_t part = document.add_mesh(mesh.parts[p]);
        const std::size_t translation = document.vec3_accessor(translations[p], 0);
        scene_nodes.push_back(document.add_node(
            {{"mesh", part}, {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", translation}}}}}}}}));
    }
    document.write(path, scene_nodes, "vdbmesh lattice", {"EXT_mesh_gpu_instancing"});
}

}  // namespace vdbmesh::cli
