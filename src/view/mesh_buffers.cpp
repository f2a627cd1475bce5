#include "view/mesh_buffers.h"

#include <cstring>

#include "vdbmesh/mesh_io.h"

namespace vdbmesh::view {

namespace {

template <typename Item>
void append(std::string& body, const std::vector<Item>& items) {
    const std::size_t bytes = items.size() * sizeof(Item);
    const std::size_t offset = body.size();
    body.resize(offset + bytes);
    if (bytes > 0) std::memcpy(body.data() + offset, items.data(), bytes);
}

}  // namespace

std::string mesh_buffers(const Mesh& mesh) {
    std::string body;
    body.reserve(24 * mesh.vertices.size() + 12 * mesh.triangles.size());
    append(body, mesh.vertices);
    append(body, vertex_normals(mesh));
    append(body, mesh.triangles);
    return body;
}

}  // namespace vdbmesh::view
