#include "view/region_mesh.h"

#include <openvdb/openvdb.h>

#include <limits>
#include <utility>
#include <vector>

namespace vdbmesh::view {
namespace {

/// The floor of @a value / kNodeVoxels, times kNodeVoxels: the origin of the node holding it.
std::int32_t node_origin(std::int32_t value) {
    const std::int32_t q = value >= 0 ? value / kNodeVoxels : -((-value + kNodeVoxels - 1) / kNodeVoxels);
    return q * kNodeVoxels;
}

/// @a source with only the nodes whose origins lie in [min, max] (node origins): what the
/// mesher meshes; samples are still read from the whole source.
class NodeSubset : public GridRegionSource {
public:
    NodeSubset(const GridRegionSource& source, const IndexBox& origins) : source_(source) {
        for (const NodeWeight& node : source.nodes()) {
            bool inside = true;
            for (int a = 0; a < 3; ++a) inside = inside && node.origin[a] >= origins.min[a] && node.origin[a] <= origins.max[a];
            if (inside) nodes_.push_back(node);
        }
    }
    std::shared_ptr<const openvdb::FloatGrid> description() const override { return source_.description(); }
    std::vector<NodeWeight> nodes() const override { return nodes_; }
    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox& box) const override { return source_.read(box); }
    std::uint64_t estimated_bytes(const IndexBox& box) const override { return source_.estimated_bytes(box); }
    std::uint64_t grid_bytes(const IndexBox& box) const override { return source_.grid_bytes(box); }

private:
    const GridRegionSource& source_;
    std::vector<NodeWeight> nodes_;
};

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

Mesh region_mesh(const GridRegionSource& source, const IndexBox& box, const MeshOptions& options) {
    // A kept triangle's corner lies in a cell of its node; the block that owns the triangle
    // (docs/dmc.md) holds the minimum sample of an edge of that cell: in the node or the next.
    // One node more on each side leaves room for vertices placed on a cell's faces.
    IndexBox origins;
    for (int a = 0; a < 3; ++a) {
        origins.min[a] = node_origin(box.min[a]) - kNodeVoxels;
        origins.max[a] = node_origin(box.max[a] - 1) + kNodeVoxels;
    }
    const NodeSubset subset(source, origins);
    BrickOptions bricks;
    if (options.method == MeshMethod::dc && options.error > 0) bricks.nodes_per_brick = 1;
    const MeshResult result = mesh_bricks(subset, options, bricks);
    return triangles_in(result.mesh, box, source.description()->transform());
}

}  // namespace vdbmesh::view
