// Placeholder until the metaimage reader lands.
#include "formats.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {
VolumeSource read_metaimage(const std::filesystem::path& path) { throw FormatError(path.string(), "format not supported yet"); }
}  // namespace vdbmesh::detail
