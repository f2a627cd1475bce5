#pragma once
// A glTF 2.0 document being built: one binary buffer, its views and accessors, meshes,
// materials and nodes; written as .glb (binary container) or .gltf (JSON with the buffer
// embedded as a base64 data URI) through CheckedOutput (nothing is left behind on failure).
// Used by the instanced lattice output and the per-label output of `mesh --labels`.

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "vdbmesh/mesh.h"

namespace vdbmesh::cli {

class GltfDocument {
public:
    using Json = nlohmann::ordered_json;
    static constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

    /// A float VEC3 accessor over @a values (with min and max), its view marked @a target (0: none).
    std::size_t vec3_accessor(const std::vector<std::array<float, 3>>& values, int target);
    /// A mesh of one triangle primitive; @a material < 0: none.
    std::size_t add_mesh(const Mesh& mesh, const std::string& name = {}, long material = -1);
    /// A metallic-roughness material of colour @a rgb (0..1), double-sided off.
    std::size_t add_material(const std::string& name, const std::array<double, 3>& rgb);
    std::size_t add_node(Json node);
    /// Writes the document with one scene of @a scene_nodes; .glb binary, else JSON.
    void write(const std::string& path, const Json& scene_nodes, const std::string& generator,
               const std::vector<std::string>& extensions_used = {}) const;

private:
    std::size_t append(const void* data, std::size_t bytes, int target);
    std::vector<unsigned char> bin_;
    Json views_ = Json::array(), accessors_ = Json::array(), meshes_ = Json::array(), materials_ = Json::array(),
         nodes_ = Json::array();
};

}  // namespace vdbmesh::cli
