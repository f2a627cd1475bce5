#pragma once
// The coarse grid of a scan: each sample the mean of a factor^3 block of the full grid, for a
// first mesh that arrives while the full one is still being made.

#include <openvdb/openvdb.h>

#include <cstdint>
#include <functional>

#include "vdbmesh/grid_region.h"

namespace vdbmesh::view {

/// The smallest factor whose coarse grid of @a box has at most @a max_samples samples.
int coarse_factor(const openvdb::CoordBBox& box, std::int64_t max_samples);

/// Averages @a grid over factor^3 blocks of @a box (blocks cut by its far faces average what
/// lies inside). Coarse voxel (0, 0, 0) is the block at box.min(), placed in the world at the
/// block's centre; its scan box is the whole coarse grid, so meshers close the surface there.
openvdb::FloatGrid::Ptr coarse_grid(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box, int factor);

/// A slab's grid (read by region) and the part of the box it holds.
using SlabVisitor = std::function<void(const openvdb::FloatGrid&, const openvdb::CoordBBox&)>;

/// Called between pieces of background work (each a fraction of a second): it may wait (a
/// pause) or throw (a stop).
using Checkpoint = std::function<void()>;

/// The same grid from @a source read in slabs of whole coarse layers about one node thick,
/// one at a time; @a visit sees each slab too (so that other passes share the read).
/// @a checkpoint is called before each coarse layer is averaged.
openvdb::FloatGrid::Ptr coarse_grid(const GridRegionSource& source, const openvdb::CoordBBox& box, int factor,
                                    const SlabVisitor& visit, const Checkpoint& checkpoint = [] {});

}  // namespace vdbmesh::view
