#pragma once
/// @file write_volume.h
/// @brief Writing volumes slice by slice in every format vdbmesh reads (used by
/// `vdbmesh phantom`, tests and benchmarks), never holding the whole volume.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "vdbmesh/read.h"

namespace vdbmesh {

/// Fills one z-slice (header.slice_voxels() floats, x fastest) with sample values.
/// Called for z = 0, 1, ... in order.
using SliceSource = std::function<void(std::int64_t z, float* slice)>;

/// Choices the file name cannot express.
struct WriteOptions {
    bool gzip = false;  ///< NRRD: "encoding: gzip" (.nhdr: the data file is .raw.gz). Other formats
                        ///< compress by name (.nii.gz, .raw.gz) and refuse this flag.
};

/// What write_volume() wrote.
struct WriteResult {
    std::vector<std::filesystem::path> files;  ///< every file written, header first (a DICOM series: its folder)
    bool value_scale_stored = true;  ///< false when the format has no scale field: readers then see the
                                     ///< stored numbers, (value - value_offset) / value_scale
};

/// Writes a volume described by @a header (dims, type, byte order, spacing/affine,
/// value scale) to @a path, in the format its extension names: .nii, .nii.gz, .hdr
/// (with header.format "analyze" an Analyze 7.5 pair, else a NIfTI pair), .dat (OpenQVis),
/// .mhd/.mha, .nrrd/.nhdr, .raw/.raw.gz; a path ending in "/" or an existing folder
/// receives a DICOM series. Samples are stored as (value - value_offset) / value_scale,
/// rounded and clamped to the sample type. Every file is written atomically.
/// The geometry comes from header.index_to_world; header.spacing must match its column
/// lengths. Formats without a value scale field (OpenQVis, MetaImage, NRRD, raw) store the
/// same numbers but cannot say how to scale them back: see WriteResult::value_scale_stored.
/// Formats refuse (Error, nothing written) what they cannot hold: a sample type they lack
/// (OpenQVis: u8, u16, f32; Analyze: u8, i16, i32, f32, f64), big-endian OpenQVis, a rotated
/// affine in Analyze, dims over 32767 in NIfTI/Analyze.
WriteResult write_volume(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices,
                         const WriteOptions& options = {});

}  // namespace vdbmesh
