#pragma once
/// @file vdb_probe.h
/// @brief A .vdb from outside is untrusted: OpenVDB's reader can crash or allocate without
/// bound on a corrupt file, so a child process reads it first (all of it, its topology, or
/// the leaves of one region) and the parent reads only what the child read without harm.

#include <cstdint>
#include <filesystem>
#include <functional>

namespace vdbmesh::detail {

/// What a forked child reads: OpenVDB's reader on one thread, no TBB work (unsafe after
/// fork()). It reports failure by throwing.
using ChildReading = std::function<void()>;

/// Reads every grid of @a path with OpenVDB in a forked child process whose address space is
/// limited (RLIMIT_AS: 64 times the file size, at least 2 GiB, at most the physical memory).
/// Throws FormatError naming the file when the child crashes (the signal), exceeds the limit,
/// or OpenVDB throws; returns when the file reads cleanly.
void probe_vdb_in_child(const std::filesystem::path& path);

/// Runs @a read_topology (the headers and every grid's topology, leaf buffers left on disk by
/// delayed loading) in a child as above, its limit the file's size (the file is mapped) plus
/// 4 times a sixteenth of it, at least 2 GiB, at most the physical memory.
void probe_vdb_topology_in_child(const std::filesystem::path& path, const ChildReading& read_topology);

/// Runs @a read_values (loading @a value_bytes of leaf values of @a path into memory shared
/// with this process) in a child as above, its limit this process's address space plus 8
/// times @a value_bytes, at least 2 GiB.
void read_region_in_child(const std::filesystem::path& path, const ChildReading& read_values, std::uint64_t value_bytes);

}  // namespace vdbmesh::detail
