#pragma once
// Private: checking and reading a .vdb file, shared by read_vdb(), open_vdb_regions() and
// describe_vdb_file().

#include <openvdb/openvdb.h>

#include <filesystem>

namespace vdbmesh::detail {

/// Throws FormatError naming @a path when it is no regular file or shorter than a .vdb header.
void require_vdb_header(const std::filesystem::path& path);

/// The first float grid of @a path, loaded through open_vdb_regions()' probe: the headers and
/// topology read by a child and then here, the leaf values decoded only by children (in
/// vdb_regions.cpp). Throws FormatError as read_vdb() does; checks no checksum.
openvdb::FloatGrid::Ptr read_first_float_grid(const std::filesystem::path& path);

/// All grids of @a path, fully loaded. Throws FormatError naming the file when it is missing
/// or OpenVDB cannot read it.
openvdb::GridPtrVecPtr read_vdb_grids(const std::filesystem::path& path);

}  // namespace vdbmesh::detail
