// Placeholder until the nrrd reader lands.
#include "formats.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {
VolumeSource read_nrrd(const std::filesystem::path& path) { throw FormatError(path.string(), "format not supported yet"); }
}  // namespace vdbmesh::detail
