// The walk of region_walk.h (from the root down through the nodes that meet the box, tiles
// copied at their own level, leaves gathered), and grid_region.h's assembly of regions by it.

#include "region_walk.h"

#include <algorithm>
#include <tuple>

namespace vdbmesh::detail::region_walk {

openvdb::CoordBBox to_bbox(const IndexBox& box) {
    return {openvdb::Coord(box.min[0], box.min[1], box.min[2]), openvdb::Coord(box.max[0] - 1, box.max[1] - 1, box.max[2] - 1)};
}

std::uint64_t TreeRegion::bytes() const {
    return sizeof(openvdb::FloatGrid) + sizeof(Tree) + upper_nodes * sizeof(Upper) + lower_nodes * sizeof(Lower) +
           leaves.size() * (sizeof(Leaf) + Leaf::SIZE * sizeof(float));
}

namespace {

/// Copies a tile of a node at @a level into region.out when it meets the box and differs from
/// the background there.
template <class Iter>
void copy_tile(const Iter& tile, openvdb::Index level, openvdb::Index tile_dim, TreeRegion& region) {
    if (!region.out || !openvdb::CoordBBox::createCube(tile.getCoord(), tile_dim).hasOverlap(region.box)) return;
    if (tile.isValueOn() || *tile != region.out->background()) region.out->addTile(level, tile.getCoord(), *tile, tile.isValueOn());
}

template <class Node>
void walk_internal(const Node& node, TreeRegion& region) {
    ++(Node::LEVEL == 1 ? region.lower_nodes : region.upper_nodes);
    for (auto tile = node.cbeginValueAll(); tile; ++tile) copy_tile(tile, Node::LEVEL, Node::ChildNodeType::DIM, region);
    for (auto child = node.cbeginChildOn(); child; ++child) {
        if (!child->getNodeBoundingBox().hasOverlap(region.box)) continue;
        if constexpr (Node::LEVEL == 1) {
            region.leaves.push_back(&*child);
        } else {
            walk_internal(*child, region);
        }
    }
}

/// The nodes of an active tile of @a dim voxels at @a origin, each all active.
void add_tile_nodes(const openvdb::Coord& origin, openvdb::Index dim, std::vector<NodeWeight>& nodes) {
    const auto step = static_cast<std::int32_t>(Lower::DIM);
    const auto end = static_cast<std::int32_t>(dim);
    for (std::int32_t z = 0; z < end; z += step)
        for (std::int32_t y = 0; y < end; y += step)
            for (std::int32_t x = 0; x < end; x += step)
                nodes.push_back({{origin.x() + x, origin.y() + y, origin.z() + z}, std::uint64_t{Lower::NUM_VOXELS}});
}

}  // namespace

std::vector<NodeWeight> node_weights(const Tree& tree) {
    std::vector<NodeWeight> nodes;
    for (auto tile = tree.root().cbeginValueOn(); tile; ++tile) add_tile_nodes(tile.getCoord(), Upper::DIM, nodes);
    for (auto upper = tree.root().cbeginChildOn(); upper; ++upper) {
        for (auto tile = upper->cbeginValueOn(); tile; ++tile) add_tile_nodes(tile.getCoord(), Lower::DIM, nodes);
        for (auto lower = upper->cbeginChildOn(); lower; ++lower) {
            const std::uint64_t active = lower->onVoxelCount();
            if (active > 0) nodes.push_back({{lower->origin().x(), lower->origin().y(), lower->origin().z()}, active});
        }
    }
    std::sort(nodes.begin(), nodes.end(), [](const NodeWeight& a, const NodeWeight& b) {
        return std::tie(a.origin[2], a.origin[1], a.origin[0]) < std::tie(b.origin[2], b.origin[1], b.origin[0]);
    });
    return nodes;
}

void walk_region(const Tree& tree, TreeRegion& region) {
    const Root& root = tree.root();
    for (auto tile = root.cbeginValueAll(); tile; ++tile) copy_tile(tile, Root::LEVEL, Upper::DIM, region);
    for (auto child = root.cbeginChildOn(); child; ++child)
        if (child->getNodeBoundingBox().hasOverlap(region.box)) walk_internal(*child, region);
}


}  // namespace vdbmesh::detail::region_walk

namespace vdbmesh {

using detail::region_walk::Leaf;
using detail::region_walk::Lower;
using detail::region_walk::TreeRegion;
using detail::region_walk::Upper;

void absorb_region(openvdb::FloatGrid& into_grid, openvdb::FloatGrid& region) {
    openvdb::FloatTree& into = into_grid.tree();
    openvdb::FloatTree& from = region.tree();
    TreeRegion tiles{openvdb::CoordBBox::inf(), &into, {}, 0, 0};
    detail::region_walk::walk_region(from, tiles);
    std::vector<Leaf*> leaves;
    from.stealNodes(leaves);  // moved, not copied: one copy of the samples at a time
    for (Leaf* leaf : leaves) into.addLeaf(leaf);
}

void drop_nodes_below(openvdb::FloatGrid& grid, std::int32_t z) {
    openvdb::FloatTree& tree = grid.tree();
    std::vector<openvdb::Coord> below;
    for (auto upper = tree.root().cbeginChildOn(); upper; ++upper) {
        for (auto lower = upper->cbeginChildOn(); lower; ++lower) {
            if (lower->origin().z() + static_cast<std::int32_t>(Lower::DIM) <= z) below.push_back(lower->origin());
        }
    }
    for (const openvdb::Coord& origin : below) tree.addTile(Upper::LEVEL, origin, tree.background(), false);
}

}  // namespace vdbmesh
