#pragma once
/// @file grid_checksum.h
/// @brief A checksum over what a .vdb we write holds, stored in the grid's metadata
/// (kMetaChecksum) and checked when the file is read back.

#include <openvdb/openvdb.h>

#include <cstdint>

namespace vdbmesh::detail {

/// A 64-bit hash of the grid's tree (every leaf's origin, masks and values, every tile), its
/// background, transform and our vdbmesh_* metadata other than kMetaChecksum. The same grid gives the same
/// value for any thread count.
std::uint64_t grid_checksum(const openvdb::FloatGrid& grid);

}  // namespace vdbmesh::detail
