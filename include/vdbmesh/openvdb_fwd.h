#pragma once
/// @file openvdb_fwd.h
/// @brief openvdb::FloatGrid declared without OpenVDB's headers (only its version macros),
/// for the public headers that take a grid by reference and need no more (mesher.h,
/// compare.h). To make, read or look into a grid, include vdbmesh/grid.h or OpenVDB itself;
/// the declarations here name the same type, so both may be included in any order.

#include <openvdb/version.h>

#include <cstdint>

namespace openvdb {
OPENVDB_USE_VERSION_NAMESPACE
namespace OPENVDB_VERSION_NAME {

using Index32 = std::uint32_t;  // as openvdb/Types.h
using Index = Index32;

template <typename TreeType>
class Grid;

namespace tree {
template <typename RootNodeType>
class Tree;
template <typename ChildType>
class RootNode;
template <typename ChildNodeType, Index Log2Dim>
class InternalNode;
template <typename T, Index Log2Dim>
class LeafNode;
}  // namespace tree

/// tree::Tree4<float, 5, 4, 3>::Type, OpenVDB's standard float tree.
using FloatTree = tree::Tree<tree::RootNode<tree::InternalNode<tree::InternalNode<tree::LeafNode<float, 3>, 4>, 5>>>;
using FloatGrid = Grid<FloatTree>;

}  // namespace OPENVDB_VERSION_NAME
}  // namespace openvdb
