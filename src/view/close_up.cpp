#include "view/close_up.h"

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

namespace vdbmesh::view {
namespace {

/// The box of whole voxels holding a node's sphere, in the index space of @a transform.
IndexBox sphere_box(const SplatNode& node, const openvdb::math::Transform& transform) {
    openvdb::Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (int corner = 0; corner < 8; ++corner) {
        openvdb::Vec3d world;
        for (int a = 0; a < 3; ++a) world[a] = node.centre[a] + ((corner >> a) & 1 ? node.radius : -node.radius);
        const openvdb::Vec3d index = transform.worldToIndex(world);
        lo = openvdb::math::minComponent(lo, index);
        hi = openvdb::math::maxComponent(hi, index);
    }
    IndexBox box;
    for (int a = 0; a < 3; ++a) {
        box.min[a] = std::int32_t(std::floor(lo[a]));
        box.max[a] = std::int32_t(std::floor(hi[a])) + 1;
    }
    return box;
}

bool overlap(const IndexBox& a, const IndexBox& b) {
    for (int i = 0; i < 3; ++i)
        if (a.max[i] <= b.min[i] || b.max[i] <= a.min[i]) return false;
    return true;
}

bool contains(const IndexBox& outer, const IndexBox& inner) {
    for (int i = 0; i < 3; ++i)
        if (inner.min[i] < outer.min[i] || inner.max[i] > outer.max[i]) return false;
    return true;
}

std::int32_t snap_down(std::int32_t v) {
    const std::int32_t q = v >= 0 ? v / kCloseUpSnapVoxels : -((-v + kCloseUpSnapVoxels - 1) / kCloseUpSnapVoxels);
    return q * kCloseUpSnapVoxels;
}

/// The triangles of the full mesh with a corner in @a box, estimated from above: the weights
/// of the largest nodes whose spheres lie inside it, and of the childless ones that meet it.
std::size_t estimated_triangles(const SplatTree& tree, const IndexBox& box, const openvdb::math::Transform& transform) {
    std::size_t crossings = 0;
    std::vector<std::uint32_t> stack{0};
    while (!stack.empty()) {
        const SplatNode& node = tree.nodes[stack.back()];
        stack.pop_back();
        const IndexBox around = sphere_box(node, transform);
        if (!overlap(around, box)) continue;
        if (node.child_count == 0 || contains(box, around)) {
            crossings += node.weight;
            continue;
        }
        for (std::uint32_t c = node.first_child; c < node.first_child + node.child_count; ++c) stack.push_back(c);
    }
    return kTrianglesPerCrossing * crossings;
}

/// How many of its surface's triangles a node's discs would cost at the view's pixel size, as
/// a ratio: over 1, triangles are cheaper.
double disc_cost_over_triangles(const SplatNode& node, const SplatView& view) {
    const double discs = std::pow(projected_splat_size(node, view) / view.pixel_size, 2);
    return discs / (double(kTrianglesPerCrossing) * std::max<std::uint32_t>(node.weight, 1));
}

/// @a box grown to hold @a more.
IndexBox joined(const IndexBox& box, const IndexBox& more) {
    IndexBox out;
    for (int a = 0; a < 3; ++a) {
        out.min[a] = std::min(box.min[a], more.min[a]);
        out.max[a] = std::max(box.max[a], more.max[a]);
    }
    return out;
}

bool centre_inside(const SplatNode& node, const IndexBox& box, const openvdb::math::Transform& transform) {
    const openvdb::Vec3d index = transform.worldToIndex(openvdb::Vec3d(node.centre[0], node.centre[1], node.centre[2]));
    for (int a = 0; a < 3; ++a)
        if (!(index[a] >= box.min[a] && index[a] < box.max[a])) return false;
    return true;
}

}  // namespace

std::optional<CloseUp> find_close_up(const SplatTree& tree, const SplatSelection& selection, const SplatView& view,
                                     const openvdb::FloatGrid& grid, std::size_t max_triangles) {
    const openvdb::math::Transform& transform = grid.transform();
    // The nodes that ask, the most pressing first; each joins the box unless it would stretch
    // it beyond kCloseUpMaxVoxels (a close-up reads the nodes round its box).
    std::vector<std::pair<double, std::uint32_t>> asking;
    for (std::uint32_t index : selection.nodes) {
        const double ratio = disc_cost_over_triangles(tree.nodes[index], view);
        if (ratio > 1) asking.emplace_back(ratio, index);
    }
    std::sort(asking.begin(), asking.end(), std::greater<>());
    CloseUp close;
    for (const auto& [ratio, index] : asking) {
        const IndexBox around = sphere_box(tree.nodes[index], transform);
        const IndexBox grown = close.nodes == 0 ? around : joined(close.box, around);
        bool fits = true;
        for (int a = 0; a < 3; ++a) fits = fits && grown.max[a] - grown.min[a] <= kCloseUpMaxVoxels;
        if (!fits) continue;
        close.box = grown;
        ++close.nodes;
    }
    if (close.nodes == 0) return std::nullopt;
    for (int a = 0; a < 3; ++a) {
        close.box.min[a] = snap_down(close.box.min[a]);
        close.box.max[a] = snap_down(close.box.max[a] - 1) + kCloseUpSnapVoxels;
    }
    close.estimated_triangles = estimated_triangles(tree, close.box, transform);
    if (close.estimated_triangles > max_triangles) return std::nullopt;
    return close;
}

std::size_t move_inside_last(const SplatTree& tree, const IndexBox& box, const openvdb::FloatGrid& grid,
                             SplatSelection& selection) {
    const auto inside_from = std::stable_partition(selection.nodes.begin(), selection.nodes.end(), [&](std::uint32_t index) {
        return !centre_inside(tree.nodes[index], box, grid.transform());
    });
    return std::size_t(selection.nodes.end() - inside_from);
}

}  // namespace vdbmesh::view
