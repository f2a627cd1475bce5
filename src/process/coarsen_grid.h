#pragma once
// Private: a grid at twice the voxel size for the triangle budget's coarse route (mesh_to_budget.cpp).

#include <memory>

#include "vdbmesh/mesher.h"
#include "vdbmesh/openvdb_fwd.h"

namespace vdbmesh::detail {

/// @brief @a grid at twice its voxel size, keeping everything inside the object: sample (i, j, k)
/// of the result is the most inside (@a inside: the largest above, the smallest below) of the
/// scanned samples (2i + a, 2j + b, 2k + c), a, b, c in {-1, 0, 1}; active when one of them is.
/// So every inside sample stays inside, and the coarse isosurface holds the fine one's solid
/// dilated by up to a fine voxel along each axis (thin walls and specks kept, gaps narrower than
/// about two voxels closed). The transform grows by 2 (sample i lies where fine sample 2i did);
/// the scanned box grows to the samples whose neighbourhood meets it; other metadata are kept.
std::shared_ptr<openvdb::FloatGrid> coarsen_grid(const openvdb::FloatGrid& grid, Inside inside);

}  // namespace vdbmesh::detail
