#pragma once
// Private: the 348-byte header shared by Analyze 7.5 and NIfTI-1, parsed from bytes alone
// (no disk access) so that it can be fuzzed.

#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "vdbmesh/read.h"

namespace vdbmesh::detail {

/// sizeof_hdr of Analyze 7.5 and NIfTI-1.
constexpr std::size_t kNiftiHeaderBytes = 348;

/// What the header says, validated.
struct NiftiAnalyzeHeader {
    VolumeHeader header;             ///< format "nifti" or "analyze"; path is the header file
    bool single_file = false;        ///< magic "n+1": the samples follow the header in the same file
    std::uint64_t vox_offset = 0;    ///< byte offset of the samples in their (decompressed) file
    std::uint64_t volume_bytes = 0;  ///< bytes of the first 3-D volume: what is read
    std::uint64_t all_bytes = 0;     ///< bytes of every volume (dims 4..7): what the data file holds
};

/// Parses and validates the first kNiftiHeaderBytes of @a bytes as NIfTI-1 (magic "n+1" or
/// "ni1") or else Analyze 7.5, in the byte order that makes sizeof_hdr 348. @a path only
/// names the file in messages. Throws FormatError naming the field on any invalid value.
NiftiAnalyzeHeader parse_nifti_analyze_header(const unsigned char* bytes, std::size_t size,
                                              const std::filesystem::path& path);

}  // namespace vdbmesh::detail
