#pragma once
// The samples a grid holds inside a box, streamed in runs: leaf voxels as they are, tiles as
// their value repeated once per voxel. Feeds the statistics and the histogram of `view`.

#include <openvdb/openvdb.h>

#include <cstddef>
#include <functional>

#include "vdbmesh/view.h"

namespace vdbmesh::view {

using SampleRunVisitor = std::function<void(const float* values, std::size_t count)>;

/// Calls @a visit with every value of @a grid at a voxel inside @a box (leaves and tiles;
/// the background outside them is left out), in runs of at most 512 values.
void for_each_sample(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box, const SampleRunVisitor& visit);

/// Counts @a count @a values into @a histogram's bins (values outside its range in the end bins).
void add_samples(ValueHistogram& histogram, const float* values, std::size_t count);

/// The histogram of the samples of @a grid inside @a box over [min, max] in @a bins equal bins
/// (values outside are counted in the end bins).
ValueHistogram sample_histogram(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box, double min, double max,
                                std::size_t bins);

}  // namespace vdbmesh::view
