#pragma once
// Private: the tags of one DICOM file that a volume needs, parsed from bytes (a file or a
// buffer, so that it can be fuzzed). The series logic (sorting, consistency) is in dicom.cpp.

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <istream>
#include <optional>
#include <string>

#include "vdbmesh/read.h"

namespace vdbmesh::detail {

/// What one slice file says. Optional fields are absent in the file when empty.
struct DicomSlice {
    std::string transfer_syntax;           ///< UID, e.g. "1.2.840.10008.1.2" (implicit VR little endian)
    ByteOrder byte_order = ByteOrder::little;
    std::string series_uid;                ///< SeriesInstanceUID (0020,000E), "" when absent
    std::int64_t rows = 0;                 ///< (0028,0010): samples along y
    std::int64_t columns = 0;              ///< (0028,0011): samples along x
    int bits_allocated = 0;                ///< (0028,0100)
    int pixel_representation = 0;          ///< (0028,0103): 0 unsigned, 1 two's complement
    int samples_per_pixel = 1;             ///< (0028,0002)
    std::int64_t frames = 1;               ///< NumberOfFrames (0028,0008)
    std::optional<std::array<double, 3>> position;     ///< ImagePositionPatient (0020,0032), mm (LPS)
    std::optional<std::array<double, 6>> orientation;  ///< ImageOrientationPatient (0020,0037): row then column cosines
    std::optional<std::array<double, 2>> pixel_spacing;  ///< PixelSpacing (0028,0030): between rows \ between columns
    std::optional<double> slice_thickness;  ///< SliceThickness (0018,0050)
    double rescale_slope = 1.0;            ///< (0028,1053)
    double rescale_intercept = 0.0;        ///< (0028,1052)
    std::uint64_t pixel_offset = 0;        ///< bytes from the start of the file to the Pixel Data value
    std::uint64_t pixel_length = 0;        ///< value length of Pixel Data (7FE0,0010) in bytes

    /// The sample type BitsAllocated and PixelRepresentation give.
    SampleType sample_type() const;
    /// Bytes of one frame of samples: rows * columns * samples_per_pixel * bits_allocated / 8.
    std::uint64_t frame_bytes() const;
};

/// Parses one file up to its Pixel Data element. Returns nothing for a file that is not a
/// DICOM image, so that a README beside the slices is skipped: no "DICM" at byte 128 and no
/// data set starting with group 0002 or 0008; or such a start whose elements cannot be
/// walked and that shows no SOPClassUID or Rows; or a DICOM file without Rows (a DICOMDIR, a
/// report). Throws FormatError naming @a file when it is a DICOM image that cannot be read as
/// uncompressed single-frame samples (compressed, truncated, corrupt, multi-frame, colour).
/// The elements are walked by read_dicom_header() (dicom_data_set.h: preamble or not, meta
/// header or not, implicit/explicit VR, sequences), not by GDCM, whose Debian build aborts
/// on corrupt files; the values are decoded here with bounds checks.
std::optional<DicomSlice> parse_dicom_slice(std::istream& in, const std::filesystem::path& file);

/// The same on a buffer (for the fuzzer).
std::optional<DicomSlice> parse_dicom_slice(const unsigned char* data, std::size_t size,
                                            const std::filesystem::path& file);

}  // namespace vdbmesh::detail
