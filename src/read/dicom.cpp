// Placeholder until the dicom reader lands.
#include "formats.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {
VolumeSource read_dicom_series(const std::filesystem::path& path) { throw FormatError(path.string(), "format not supported yet"); }
}  // namespace vdbmesh::detail
