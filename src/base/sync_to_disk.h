#pragma once
/// @file sync_to_disk.h
/// @brief fsync of a finished output before it is renamed into place.

#include <filesystem>

namespace vdbmesh::detail {

/// Flushes @a path to the disk: a file, or a folder with the files directly inside it.
/// Throws Error naming @a name when the system reports a failure (a full disk, an I/O error).
void sync_to_disk(const std::filesystem::path& path, const std::filesystem::path& name);

}  // namespace vdbmesh::detail
