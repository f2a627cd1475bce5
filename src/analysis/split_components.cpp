// split_components(): the connected components of a mesh, labelled by the topology pass of
// analyze_mesh() (topology.cpp), copied out as separate meshes.
#include <limits>

#include "vdbmesh/geometry.h"
#include "vdbmesh/measure.h"

namespace vdbmesh {

std::vector<Mesh> split_components(const Mesh& mesh) {
    detail::check_indices(mesh);
    const detail::Topology topology = detail::analyze_topology(mesh);
    std::vector<Mesh> components(topology.components);
    constexpr std::uint32_t kUnmapped = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> new_index(mesh.vertices.size(), kUnmapped);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        Mesh& component = components[topology.component_of_triangle[i]];
        std::array<std::uint32_t, 3> triangle{};
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.triangles[i][k];
            if (new_index[v] == kUnmapped) {  // a vertex belongs to one component only
                new_index[v] = std::uint32_t(component.vertices.size());
                component.vertices.push_back(mesh.vertices[v]);
            }
            triangle[k] = new_index[v];
        }
        component.triangles.push_back(triangle);
    }
    return components;
}

}  // namespace vdbmesh
