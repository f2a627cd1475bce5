#pragma once
// Private: reading every grid of a .vdb file, shared by read_vdb() and describe_vdb_file().

#include <openvdb/openvdb.h>

#include <filesystem>

namespace vdbmesh::detail {

/// All grids of @a path, fully loaded. Throws FormatError naming the file when it is missing
/// or OpenVDB cannot read it.
openvdb::GridPtrVecPtr read_vdb_grids(const std::filesystem::path& path);

}  // namespace vdbmesh::detail
