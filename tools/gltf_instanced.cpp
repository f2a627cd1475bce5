#include "gltf_instanced.h"

#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>

#include "load_grid.h"  // lowercase_extension
#include "vdbmesh/checked_output.h"
#include "vdbmesh/json_text.h"

namespace vdbmesh::cli {

namespace {

constexpr int kFloat = 5126, kUnsignedInt = 5125, kArrayBuffer = 34962, kElementArrayBuffer = 34963;

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

void write_instanced_gltf(const InstancedMesh& mesh, const std::string& path) {
    using Json = nlohmann::ordered_json;
    std::vector<unsigned char> bin;
    Json views = Json::array(), accessors = Json::array(), meshes = Json::array(), nodes = Json::array(), scene_nodes = Json::array();
    auto append = [&](const void* data, std::size_t bytes, int target) {
        while (bin.size() % 4) bin.push_back(0);
        const std::size_t offset = bin.size();
        bin.resize(offset + bytes);
        std::memcpy(bin.data() + offset, data, bytes);
        Json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
        if (target) view["target"] = target;
        views.push_back(view);
        return views.size() - 1;
    };
    auto vec3_accessor = [&](const std::vector<std::array<float, 3>>& v, int target) {
        std::array<float, 3> lo{}, hi{};
        if (!v.empty()) lo = hi = v[0];
        for (const auto& p : v)
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], p[a]);
                hi[a] = std::max(hi[a], p[a]);
            }
        const std::size_t view = append(v.data(), v.size() * 12, target);
        accessors.push_back({{"bufferView", view}, {"componentType", kFloat}, {"count", v.size()}, {"type", "VEC3"}, {"min", lo}, {"max", hi}});
        return accessors.size() - 1;
    };
    // Instances grouped by part, in part order.
    std::vector<std::vector<std::array<float, 3>>> translations(mesh.parts.size());
    for (const auto& i : mesh.instances) {
        translations[i.part].push_back({float(i.translation[0]), float(i.translation[1]), float(i.translation[2])});
    }
    for (std::size_t p = 0; p < mesh.parts.size(); ++p) {
        const Mesh& part = mesh.parts[p];
        const std::size_t position = vec3_accessor(part.vertices, kArrayBuffer);
        const std::size_t index_view = append(part.triangles.data(), part.triangles.size() * 12, kElementArrayBuffer);
        accessors.push_back({{"bufferView", index_view}, {"componentType", kUnsignedInt}, {"count", part.triangles.size() * 3}, {"type", "SCALAR"}});
        const std::size_t indices = accessors.size() - 1;
        meshes.push_back({{"primitives", Json::array({{{"attributes", {{"POSITION", position}}}, {"indices", indices}, {"mode", 4}}})}});
        const std::size_t translation = vec3_accessor(translations[p], 0);
        nodes.push_back({{"mesh", p}, {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", translation}}}}}}}});
        scene_nodes.push_back(p);
    }
    while (bin.size() % 4) bin.push_back(0);
    const bool binary = lowercase_extension(path) == ".glb";
    Json buffer = {{"byteLength", bin.size()}};
    if (!binary) buffer["uri"] = "data:application/octet-stream;base64," + base64(bin);
    Json gltf = {{"asset", {{"version", "2.0"}, {"generator", "vdbmesh lattice"}}},
                 {"extensionsUsed", {"EXT_mesh_gpu_instancing"}},
                 {"scene", 0},
                 {"scenes", Json::array({{{"nodes", scene_nodes}}})},
                 {"nodes", nodes},
                 {"meshes", meshes},
                 {"accessors", accessors},
                 {"bufferViews", views},
                 {"buffers", Json::array({buffer})}};
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
