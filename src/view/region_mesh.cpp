#include "view/region_mesh.h"

#include <openvdb/openvdb.h>

#include "vdbmesh/error.h"

#include <limits>
#include <string>
#include <vector>

namespace vdbmesh::view {
namespace {

/// Two leaves round the nodes read, as the bricked mesher reads a whole region (a block's
/// sample window is -1..9 voxels from its origin).
constexpr std::int32_t kWindowVoxels = 16;

/// The floor of @a value / kNodeVoxels, times kNodeVoxels: the origin of the node holding it.
std::int32_t node_origin(std::int32_t value) {
    const std::int32_t q = value >= 0 ? value / kNodeVoxels : -((-value + kNodeVoxels - 1) / kNodeVoxels);
    return q * kNodeVoxels;
}

/// The triangles of @a mesh with a corner inside @a box (index space of @a transform), and
/// the vertices they use, both in their order.
Mesh triangles_in(const Mesh& mesh, const IndexBox& box, const openvdb::math::Transform& transform) {
    std::vector<char> inside(mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        const auto& p = mesh.vertices[v];
        const openvdb::Vec3d index = transform.worldToIndex(openvdb::Vec3d(p[0], p[1], p[2]));
        bool in = true;
        for (int a = 0; a < 3; ++a) in = in && index[a] >= box.min[a] && index[a] < box.max[a];
        inside[v] = in;
    }
    constexpr auto kUnused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> renumbered(mesh.vertices.size(), kUnused);
    Mesh out;
    for (const auto& triangle : mesh.triangles) {
        if (!inside[triangle[0]] && !inside[triangle[1]] && !inside[triangle[2]]) continue;
        std::array<std::uint32_t, 3> kept{};
        for (int c = 0; c < 3; ++c) {
            std::uint32_t& index = renumbered[triangle[c]];
            if (index == kUnused) {
                index = std::uint32_t(out.vertices.size());
                out.vertices.push_back(mesh.vertices[triangle[c]]);
            }
            kept[c] = index;
        }
        out.triangles.push_back(kept);
    }
    return out;
}

}  // namespace

IndexBox region_read_box(const IndexBox& box) {
    // A kept triangle's corner lies in a cell of its node; the block that owns the triangle
    // (docs/dmc.md, "Bricks") holds the minimum sample of an edge of that cell: in that node or
    // the next one up. Every decision about an owned triangle reads at most one node away, so
    // the owners are meshed right from the nodes one below to two above the box's, read whole
    // with the two leaves of sample windows round them (all the other meshers read less).
    IndexBox read_box;
    for (int a = 0; a < 3; ++a) {
        read_box.min[a] = node_origin(box.min[a]) - kNodeVoxels - kWindowVoxels;
        read_box.max[a] = node_origin(box.max[a] - 1) + 3 * kNodeVoxels + kWindowVoxels;
    }
    return read_box;
}

Mesh region_mesh(const GridRegionSource& source, const IndexBox& box, const MeshOptions& options,
                 std::uint64_t max_read_bytes) {
    const IndexBox read_box = region_read_box(box);
    const std::uint64_t bytes = source.estimated_bytes(read_box);
    if (bytes > max_read_bytes)
        throw UsageError("box: its close-up reads about " + std::to_string(bytes >> 20) + " MB of the grid, over the " +
                         std::to_string(max_read_bytes >> 20) + " MB allowed; ask for a smaller box");
    const MeshResult result = mesh_grid(*source.read(read_box), options);
    return triangles_in(result.mesh, box, source.description()->transform());
}

}  // namespace vdbmesh::view
