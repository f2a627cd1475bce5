#pragma once
// Private: the bytes-level entry points of the text-header formats. Each takes the header
// text (as read from the start of @a path; binary data after the header is fine) and the
// header's path (for messages and for resolving relative data files). They never read a
// file: they only ask whether data files exist and how long they are (for the size checks
// and "data at the end of the file"); NRRD's "line skip" goes through a callback. So a
// fuzzer can drive them with any text. Every problem is a FormatError naming the field.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string_view>

#include "vdbmesh/read.h"

namespace vdbmesh::detail {

/// OpenQVis .dat (format.cpp of the QVis volume renderer: Key: value lines).
VolumeSource parse_openqvis_header(std::string_view text, const std::filesystem::path& path);

/// MetaImage .mhd/.mha (ITK MetaIO: Key = Value lines ending with ElementDataFile).
VolumeSource parse_metaimage_header(std::string_view text, const std::filesystem::path& path);

/// Bytes taken by the first @a lines lines of @a file from byte @a offset on (NRRD "line skip").
using LineSkipper = std::function<std::uint64_t(const std::filesystem::path& file, std::uint64_t offset, std::int64_t lines)>;

/// NRRD .nrrd/.nhdr (teem's NRRD0001-5 format). @a skip_lines is asked only when the header
/// has a "line skip" field; read_nrrd() passes one that reads the data file.
VolumeSource parse_nrrd_header(std::string_view text, const std::filesystem::path& path, const LineSkipper& skip_lines);

}  // namespace vdbmesh::detail
