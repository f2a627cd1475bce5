#pragma once
// Private: one parser per format, each in its own file, all returning a VolumeSource.
// The dispatcher (open_volume.cpp) picks one by extension or content.

#include "vdbmesh/read.h"

namespace vdbmesh::detail {

VolumeSource read_nifti_or_analyze(const std::filesystem::path& path);  // nifti_analyze.cpp: .nii .nii.gz .hdr/.img
VolumeSource read_openqvis(const std::filesystem::path& path);          // openqvis.cpp: .dat
VolumeSource read_metaimage(const std::filesystem::path& path);         // metaimage.cpp: .mhd .mha
VolumeSource read_nrrd(const std::filesystem::path& path);              // nrrd.cpp: .nrrd .nhdr
VolumeSource read_raw(const std::filesystem::path& path, const ReadOptions& options);  // raw.cpp
VolumeSource read_dicom_series(const std::filesystem::path& folder);    // dicom.cpp

/// What the sample data of @a header must hold, as every truncation message says it: "8000 bytes
/// of samples (20 x 20 x 20 u8)", with " in N files" when @a files > 1 (volume_reader.cpp).
std::string describe_sample_bytes(const VolumeHeader& header, std::size_t files);

/// Throws Error (internal) unless @a part lies within a slice of @a header (slice_reader.cpp).
void check_slice_part(const VolumeHeader& header, const SliceRectangle& part);

}  // namespace vdbmesh::detail
