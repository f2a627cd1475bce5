#pragma once
/// @file shared_process.h
/// @brief Process simulation on the shared tree (Parker and Udeshi, section 4): conformal
/// deposition, directional etching down to a stop layer, CSG with another grid; each with
/// result matching (one computation per distinct 27-node neighbourhood), and the plain
/// references that apply the same per-voxel rule to an expanded grid. OpenVDB-free: grids are
/// only declared. Inputs are narrow-band level sets (negative inside); see shared_process.cpp
/// for the exact rules.

#include <memory>

#include "vdbmesh/openvdb_fwd.h"
#include "vdbmesh/shared_tree.h"

namespace vdbmesh {

/// Grows the solid by @a distance (world units): every point within @a distance of it.
/// Passes of at most 7 voxels each. @throw UsageError for a negative or non-finite distance.
SharedTree shared_deposit(const SharedTree& tree, double distance);
/// Removes material reached from outside along axis @a axis (0 x, 1 y, 2 z) looking towards
/// @a sign (+1: the exposed side is at +axis; material up to @a depth below it goes), never
/// removing or etching through the stop layer (a level set, negative inside; may be null).
SharedTree shared_etch(const SharedTree& tree, int axis, int sign, double depth, const openvdb::FloatGrid* stop);

enum class CsgOp { unite, intersect, subtract };
/// The tree combined voxel by voxel with @a other (same voxel size and background).
SharedTree shared_csg(const SharedTree& tree, const openvdb::FloatGrid& other, CsgOp op);

/// Plain references on an expanded grid (every leaf and its neighbours computed).
std::shared_ptr<openvdb::FloatGrid> plain_deposit(const openvdb::FloatGrid& grid, double distance);
std::shared_ptr<openvdb::FloatGrid> plain_etch(const openvdb::FloatGrid& grid, int axis, int sign, double depth,
                                               const openvdb::FloatGrid* stop);
std::shared_ptr<openvdb::FloatGrid> plain_csg(const openvdb::FloatGrid& grid, const openvdb::FloatGrid& other, CsgOp op);

}  // namespace vdbmesh
