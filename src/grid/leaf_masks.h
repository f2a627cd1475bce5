#pragma once
// Private: GridRegionSource::active_leaves() of a float tree (the default reads the region
// first; a .vdb's source walks the topology it holds).

#include <openvdb/openvdb.h>

#include <vector>

#include "vdbmesh/grid_region.h"

namespace vdbmesh::detail {

/// The leaves of @a tree holding an active voxel inside @a box, their masks cleared outside
/// it, z-major. Reads only the leaves' masks (a delay-loaded leaf's values stay on disk).
std::vector<LeafMask> leaf_masks(const openvdb::FloatTree& tree, const IndexBox& box);

}  // namespace vdbmesh::detail
