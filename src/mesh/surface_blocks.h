#pragma once
// Private: the 8^3 blocks of cells a mesher must visit.

#include <openvdb/openvdb.h>

#include <optional>
#include <vector>

#include "mesh/sample_classifier.h"

namespace vdbmesh::detail {

/// Edge length of a block of cells, equal to the leaf node's, so blocks align with leaves.
inline constexpr int kBlockDim = int(openvdb::FloatTree::LeafNodeType::DIM);

/// The origins (multiples of kBlockDim, sorted, unique) of the blocks holding the minimum
/// corner of every cell whose 8 samples are not all inside or all outside according to
/// @a classifier: the blocks next to each leaf node, the shells of tiles classified unlike
/// the background, and the shell of the scan box where it meets inside samples.
/// With @a within, only the origins inside it; the leaves visited are those near it, so a
/// region's blocks cost what the region holds, not the grid.
std::vector<openvdb::Coord> surface_blocks(const openvdb::FloatGrid& grid, const SampleClassifier& classifier,
                                           const std::optional<openvdb::CoordBBox>& within = std::nullopt);

/// False when every sample the cells of the block at @a origin read (origin .. origin + 8) is
/// on the same side, so the block holds no surface. It reads leaf buffers and tiles in place
/// and stops at the first pair of samples on either side: about a third of surface_blocks()
/// hold no surface on the scans, and loading their samples to find that out cost several
/// times more.
bool block_may_hold_surface(openvdb::FloatGrid::ConstAccessor& accessor, const SampleClassifier& classifier,
                            const openvdb::Coord& origin);

}  // namespace vdbmesh::detail
