#pragma once
// Private: walks the elements of one DICOM file up to Pixel Data, every length checked
// against the stream, keeping the values of the top-level elements asked for. It is the
// only code that interprets DICOM bytes when reading, so that a truncated or corrupt file
// ends in a clean answer: the GDCM library Debian ships keeps its assertions, and its
// reader aborts the process on such files (found by tests/fuzz/fuzz_dicom.cpp).

#include <cstdint>
#include <istream>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "vdbmesh/read.h"

namespace vdbmesh::detail {

/// A tag as (group << 16) | element.
using DicomTag = std::uint32_t;
constexpr DicomTag dicom_tag(std::uint16_t group, std::uint16_t element) {
    return (static_cast<DicomTag>(group) << 16) | element;
}
/// The value length that marks an undefined length (sequences, encapsulated pixel data).
constexpr std::uint32_t kDicomUndefinedLength = 0xffffffffu;

/// What the walk found.
struct DicomHeader {
    bool part10 = false;          ///< a 128-byte preamble and "DICM"
    bool meta_header = false;     ///< group 0002 elements before the data set
    std::string transfer_syntax;  ///< (0002,0010), or the UID of the encoding a bare data set shows
    ByteOrder byte_order = ByteOrder::little;
    std::map<DicomTag, std::string> values;   ///< raw values of the wanted top-level elements met
    std::optional<std::uint64_t> pixel_offset;  ///< first byte of the Pixel Data (7FE0,0010) value
    std::uint32_t pixel_length = 0;            ///< its value length (kDicomUndefinedLength: encapsulated)
    std::string broken;  ///< why the walk stopped before Pixel Data or the end of the stream ("" if it did not)
};

/// Walks @a in from its start: the preamble, the meta header (group 0002, explicit VR
/// little-endian, or implicit in old files), then the data set in the encoding its
/// TransferSyntaxUID names (or, without one, that its first element shows), up to Pixel Data
/// (7FE0,0010) or the end. Sequences (defined or undefined length, items, delimiters; an
/// undefined-length UN as implicit VR little-endian) are skipped, so only top-level values
/// are kept. Returns nothing when the stream does not start like DICOM: no "DICM" at byte
/// 128 and no first tag in group 0002 or 0008 (either byte order). Encodings: DICOM PS3.10
/// section 7.1 (file format), PS3.5 sections 7.1 (data elements) and 7.5 (nesting).
std::optional<DicomHeader> read_dicom_header(std::istream& in, const std::set<DicomTag>& wanted);

}  // namespace vdbmesh::detail
