#pragma once
// Private: the sign components of a leaf's sample block that the block encloses. Marching
// Cubes gives each a closed surface of its own (a speck of noise at the threshold, a pore);
// a merged octree cell whose ring holds part of one could take the vertex of the other side
// and, with its neighbours doing the same, make that surface vanish.

#include <array>

#include "mesh/dmc_grid.h"

namespace vdbmesh::detail {

constexpr int kBlockSamples = SampleBlock::kDim * SampleBlock::kDim * SampleBlock::kDim;

/// Per sample of @a block (SampleBlock::index), whether the 6-connected component of samples
/// on its side of the isovalue never reaches the block's outer layer.
std::array<bool, kBlockSamples> enclosed_components(const SampleBlock& block);

}  // namespace vdbmesh::detail
