#pragma once
// Helpers of the tests of grids read by region (grid_region.h): a region compared voxel by
// voxel with the whole grid, and the nodes counted voxel by voxel.

#include <openvdb/openvdb.h>

#include <limits>
#include <vector>

#include "vdbmesh/grid_region.h"

namespace vdbmesh::test {

inline constexpr std::int32_t kFar = std::numeric_limits<std::int32_t>::max();
/// A box holding every voxel a grid of ours can have.
inline constexpr IndexBox kEverything{{-kFar, -kFar, -kFar}, {kFar, kFar, kFar}};

/// Every voxel of @a box (clipped to where @a whole has leaves or tiles, widened by a leaf) has
/// in @a part the value and active state it has in @a whole (gtest failures, the first 5).
void expect_same_inside(const openvdb::FloatGrid& whole, const openvdb::FloatGrid& part, const IndexBox& box);

/// The nodes of @a grid counted voxel by voxel (tiles by their size), in z-major order.
std::vector<NodeWeight> nodes_counted(const openvdb::FloatGrid& grid);

void expect_same_nodes(const std::vector<NodeWeight>& actual, const std::vector<NodeWeight>& expected);

}  // namespace vdbmesh::test
