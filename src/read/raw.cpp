// Placeholder until the raw reader lands.
#include "formats.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {
VolumeSource read_raw(const std::filesystem::path& path, const ReadOptions&) { throw FormatError(path.string(), "format not supported yet"); }
}  // namespace vdbmesh::detail
