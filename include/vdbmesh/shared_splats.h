#pragma once
/// @file shared_splats.h
/// @brief The splat hierarchy of a shared tree's level set (a periodic lattice of 4096^3 voxels
/// and more), with result matching: the subtree of a 128^3 node (splat levels 0 to 6) depends
/// only on the node and its 26 neighbours (a cell's closed cube and its gradients reach one
/// node over), so it is fitted once per distinct neighbourhood and placed by translation.
/// The levels above (7 to the root) are built over the placed nodes as build_splat_tree()
/// builds them. OpenVDB-free.

#include <array>
#include <cstdint>
#include <vector>

#include "vdbmesh/splats.h"

namespace vdbmesh {

class SharedTree;

/// The level of a splat node covering a 128^3 node (the unit fitted once per neighbourhood).
inline constexpr std::uint8_t kSplatNodeLevel = 6;

struct SharedSplatTree {
    /// Levels kSplatNodeLevel to the root, breadth-first (nodes[0] the root). Its level-6 nodes
    /// are childless here and last: nodes[first_placed + i] stands for placed[i].
    SplatTree top;
    std::size_t first_placed = 0;
    /// A 128^3 node's subtree: its root (level 6) first, breadth-first, centres relative to the
    /// node's origin (world units).
    std::vector<std::vector<SplatNode>> subtrees;
    struct Placed {
        std::uint32_t subtree = 0;
        std::array<double, 3> offset{};  ///< world position of the node's origin
    };
    std::vector<Placed> placed;

    /// Nodes the tree represents (what build_splat_tree() of the expanded grid would hold).
    std::uint64_t represented_nodes() const;
};

/// The splat hierarchy of @a tree's zero level set (inside below), fitting each distinct 128^3
/// neighbourhood once. The same nodes as build_splat_tree(*to_float_grid(tree)) up to float
/// rounding of the translated centres. Throws UsageError on a negative tolerance.
SharedSplatTree build_splat_tree(const SharedTree& tree, const SplatOptions& options);

/// What a view shows of a shared tree: select_splats()'s figures (its nodes left empty) and the
/// nodes themselves, placed.
struct SharedSplatSelection {
    SplatSelection summary;
    std::vector<SplatNode> nodes;
};

/// select_splats() over the tree the shared one represents, descending into the placed subtrees.
SharedSplatSelection select_splats(const SharedSplatTree& tree, const SplatView& view);

}  // namespace vdbmesh
