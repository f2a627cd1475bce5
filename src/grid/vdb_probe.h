#pragma once
/// @file vdb_probe.h
/// @brief A .vdb from outside is untrusted: OpenVDB's reader can crash or allocate without
/// bound on a corrupt file, so a child process reads it first.

#include <filesystem>

namespace vdbmesh::detail {

/// Reads every grid of @a path with OpenVDB in a forked child process whose address space is
/// limited (RLIMIT_AS: 64 times the file size, at least 2 GiB, at most the physical memory).
/// Throws FormatError naming the file when the child crashes (the signal), exceeds the limit,
/// or OpenVDB throws; returns when the file reads cleanly.
void probe_vdb_in_child(const std::filesystem::path& path);

}  // namespace vdbmesh::detail
