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

}  // namespace vdbmesh::detail
