// A glTF 2.0 document: buffer, accessors, meshes, materials, nodes, and the .glb/.gltf writer.

#include "gltf_document.h"

#include <algorithm>
#include <cstring>

#include "load_grid.h"  // lowercase_extension
#include "vdbmesh/checked_output.h"
#include "vdbmesh/json_text.h"

namespace vdbmesh::cli {
namespace {

constexpr int kFloat = 5126, kUnsignedInt = 5125;

std::string base64(const std::vector<unsigned char>& data) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((data.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < data.size(); i += 3) {
        const unsigned b0 = data[i], b1 = i + 1 < data.size() ? data[i + 1] : 0, b2 = i + 2 < data.size() ? data[i + 2] : 0;
        const unsigned v = (b0 << 16) | (b1 << 8) | b2;
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += i + 1 < data.size() ? table[(v >> 6) & 63] : '=';
        out += i + 2 < data.size() ? table[v & 63] : '=';
    }
    return out;
}

}  // namespace

std::size_t GltfDocument::append(const void* data, std::size_t bytes, int target) {
    while (bin_.size() % 4) bin_.push_back(0);
    const std::size_t offset = bin_.size();
    bin_.resize(offset + bytes);
    if (bytes) std::memcpy(bin_.data() + offset, data, bytes);
    Json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
    if (target) view["target"] = target;
    views_.push_back(view);
    return views_.size() - 1;
}

std::size_t GltfDocument::vec3_accessor(const std::vector<std::array<float, 3>>& values, int target) {
    std::array<float, 3> lo{}, hi{};
    if (!values.empty()) lo = hi = values[0];
    for (const auto& p : values)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    const std::size_t view = append(values.data(), values.size() * 12, target);
    accessors_.push_back({{"bufferView", view}, {"componentType", kFloat}, {"count", values.size()}, {"type", "VEC3"}, {"min", lo}, {"max", hi}});
    return accessors_.size() - 1;
}

std::size_t GltfDocument::add_mesh(const Mesh& mesh, const std::string& name, long material) {
    const std::size_t position = vec3_accessor(mesh.vertices, kArrayBuffer);
    const std::size_t index_view = append(mesh.triangles.data(), mesh.triangles.size() * 12, kElementArrayBuffer);
    accessors_.push_back({{"bufferView", index_view}, {"componentType", kUnsignedInt}, {"count", mesh.triangles.size() * 3}, {"type", "SCALAR"}});
    Json primitive = {{"attributes", {{"POSITION", position}}}, {"indices", accessors_.size() - 1}, {"mode", 4}};
    if (material >= 0) primitive["material"] = material;
    Json entry = {{"primitives", Json::array({primitive})}};
    if (!name.empty()) entry["name"] = name;
    meshes_.push_back(entry);
    return meshes_.size() - 1;
}

std::size_t GltfDocument::add_material(const std::string& name, const std::array<double, 3>& rgb) {
    materials_.push_back({{"name", name},
                          {"pbrMetallicRoughness", {{"baseColorFactor", {rgb[0], rgb[1], rgb[2], 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.8}}}});
    return materials_.size() - 1;
}

std::size_t GltfDocument::add_node(Json node) {
    nodes_.push_back(std::move(node));
    return nodes_.size() - 1;
}

void GltfDocument::write(const std::string& path, const Json& scene_nodes, const std::string& generator,
                         const std::vector<std::string>& extensions_used) const {
    std::vector<unsigned char> bin = bin_;
    while (bin.size() % 4) bin.push_back(0);
    const bool binary = lowercase_extension(path) == ".glb";
    Json buffer = {{"byteLength", bin.size()}};
    if (!binary) buffer["uri"] = "data:application/octet-stream;base64," + base64(bin);
    Json gltf = {{"asset", {{"version", "2.0"}, {"generator", generator}}}};
    if (!extensions_used.empty()) gltf["extensionsUsed"] = extensions_used;
    gltf["scene"] = 0;
    gltf["scenes"] = Json::array({{{"nodes", scene_nodes}}});
    gltf["nodes"] = nodes_;
    gltf["meshes"] = meshes_;
    if (!materials_.empty()) gltf["materials"] = materials_;
    gltf["accessors"] = accessors_;
    gltf["bufferViews"] = views_;
    gltf["buffers"] = Json::array({buffer});
    CheckedOutput out(path);
    if (!binary) {
        out.stream() << detail::json_text(gltf) << "\n";
    } else {
        std::string text = detail::json_text(gltf);
        while (text.size() % 4) text += ' ';
        auto u32 = [&](std::uint32_t v) { out.stream().write(reinterpret_cast<const char*>(&v), 4); };
        u32(0x46546C67);  // "glTF"
        u32(2);
        u32(std::uint32_t(12 + 8 + text.size() + 8 + bin.size()));
        u32(std::uint32_t(text.size()));
        u32(0x4E4F534A);  // "JSON"
        out.stream().write(text.data(), std::streamsize(text.size()));
        u32(std::uint32_t(bin.size()));
        u32(0x004E4942);  // "BIN\0"
        out.stream().write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
    }
    out.commit();
}

}  // namespace vdbmesh::cli
