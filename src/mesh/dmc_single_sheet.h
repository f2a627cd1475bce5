#pragma once
// Private: the topology test of Dual Marching Cubes' octree merging (Schaefer and Warren 2004,
// section 3: a merged cell must keep the surface a single sheet), by bit operations.

#include "mesh/dmc_grid.h"

namespace vdbmesh::detail {

/// Whether the surface through the cube of @a n^3 samples of @a block at local minimum corner
/// (x, y, z) (n <= 10) is a single disc: inside and outside samples each form one 6-connected
/// component, and so do they on the cube's boundary shell (one crossing loop).
bool single_sheet(const SampleBlock& block, int x, int y, int z, int n);

}  // namespace vdbmesh::detail
