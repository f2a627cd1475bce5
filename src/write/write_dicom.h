#pragma once
// Private: writes a volume as a DICOM series, one file per slice (used by write_volume for
// a folder target, and by the DICOM reader's tests).

#include <filesystem>
#include <string>

#include "vdbmesh/read.h"
#include "vdbmesh/write_volume.h"

namespace vdbmesh::detail {

struct DicomWriteOptions {
    /// Name the files in an order that is not the slice order (tests: the reader must sort by position).
    bool shuffle_names = false;
    /// SeriesInstanceUID to write; empty: derived from the header (deterministic).
    std::string series_uid;
    /// Write bare implicit-VR little-endian data sets without preamble or meta header, as
    /// some old scanners did (default: Part 10 files, explicit VR).
    bool bare = false;
};

/// Writes @a header.dims[2] files "slice_NNNN.dcm" into the new folder @a folder (which may
/// exist only when empty): CT Image Storage, explicit VR little endian (big endian when
/// header.byte_order is big), integer samples of header.type (u8 i8 u16 i16 u32 i32) stored as
/// (value - value_offset) / value_scale rounded and clamped, RescaleSlope/Intercept from the
/// value scale, ImagePositionPatient/ImageOrientationPatient/PixelSpacing/SliceThickness from
/// header.index_to_world (whose first two columns must be orthogonal; a third column against
/// their cross product makes a reader sort the slices the other way). The series is written
/// into a temporary folder renamed into place at the end: a failed run leaves nothing.
/// Returns the folder as the one file written. Throws Error on a bad header or an I/O failure.
WriteResult write_dicom_series(const std::filesystem::path& folder, const VolumeHeader& header, const SliceSource& slices,
                        const DicomWriteOptions& options = {});

}  // namespace vdbmesh::detail
