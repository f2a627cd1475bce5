// Placeholder until the nifti_analyze reader lands.
#include "formats.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {
VolumeSource read_nifti_or_analyze(const std::filesystem::path& path) { throw FormatError(path.string(), "format not supported yet"); }
}  // namespace vdbmesh::detail
