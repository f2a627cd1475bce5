#pragma once
/// @file write_volume.h
/// @brief Writing volumes slice by slice in every format vdbmesh reads (used by
/// `vdbmesh phantom`, tests and benchmarks), never holding the whole volume.

#include <cstdint>
#include <filesystem>
#include <functional>

#include "vdbmesh/read.h"

namespace vdbmesh {

/// Fills one z-slice (header.slice_voxels() floats, x fastest) with sample values.
/// Called for z = 0, 1, ... in order.
using SliceSource = std::function<void(std::int64_t z, float* slice)>;

/// Writes a volume described by @a header (dims, type, byte order, spacing/affine,
/// value scale) to @a path, in the format its extension names: .nii, .nii.gz, .hdr
/// (with header.format "analyze" an Analyze 7.5 pair, else a NIfTI pair), .dat (OpenQVis),
/// .mhd/.mha, .nrrd/.nhdr, .raw/.raw.gz; a path ending in "/" or an existing folder
/// receives a DICOM series. Samples are stored as (value - value_offset) / value_scale,
/// rounded and clamped to the sample type. Every file is written atomically.
void write_volume(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices);

}  // namespace vdbmesh
