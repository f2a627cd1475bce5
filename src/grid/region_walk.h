#pragma once
// Private: the part of a float tree that meets a box (grid_region.h's read()): its tiles copied
// as the walk meets them, its leaves gathered for the caller to copy or load. Shared by the .vdb
// read by region (vdb_regions.cpp) and the scan read by region (scan_regions.cpp).

#include <openvdb/openvdb.h>

#include <cstdint>
#include <vector>

#include "vdbmesh/grid_region.h"

namespace vdbmesh::detail::region_walk {

using Tree = openvdb::FloatTree;
using Root = Tree::RootNodeType;
using Upper = Root::ChildNodeType;   // level 2: 4096^3 voxels
using Lower = Upper::ChildNodeType;  // level 1: the 128^3 node of grid_region.h
using Leaf = Tree::LeafNodeType;
static_assert(Lower::DIM == static_cast<openvdb::Index>(kNodeVoxels), "a node of grid_region.h is the level-1 internal node");

/// @a box as OpenVDB's inclusive box.
openvdb::CoordBBox to_bbox(const IndexBox& box);

/// What of a tree meets a box: its tiles that are active or differ from the background are
/// added to `out` (when given) as the walk meets them; its leaves are gathered (the walk never
/// touches a leaf's values, which may still be on disk).
struct TreeRegion {
    const openvdb::CoordBBox box;
    Tree* out = nullptr;
    std::vector<const Leaf*> leaves;
    std::uint64_t lower_nodes = 0, upper_nodes = 0;
    /// The bytes a tree of what was met holds (nodes, leaves with their values).
    std::uint64_t bytes() const;
};

/// Walks the nodes of @a tree that meet region.box.
void walk_region(const Tree& tree, TreeRegion& region);

/// GridRegionSource::nodes() of @a tree: every node holding an active voxel (from the masks
/// alone: no leaf buffer is loaded) or lying in an active tile, z-major.
std::vector<NodeWeight> node_weights(const Tree& tree);

}  // namespace vdbmesh::detail::region_walk
