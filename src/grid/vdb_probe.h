#pragma once
/// @file vdb_probe.h
/// @brief A .vdb from outside is untrusted: OpenVDB's reader can crash or allocate without
/// bound on a corrupt file, so a child process reads it first (all of it, its topology, or
/// the leaves of one region) and the parent reads only what the child read without harm.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

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

/// Seconds a child may take to read @a bytes of a sound file: generous (a sound file reads at
/// hundreds of MB/s), yet a reader that loops on a corrupt one is stopped within seconds.
unsigned reading_seconds(std::uintmax_t bytes);

/// The address space this process holds now (a forked child starts with all of it).
std::uint64_t address_space_now();

/// Prepares a freshly forked reading child: default signal handlers, no core file, at most
/// @a address_space bytes of address space, stderr to /dev/null (glibc's and OpenVDB's own
/// complaints).
void enter_reading_child(std::uint64_t address_space);

/// The text a reading child reports when @a reading throws, empty when it returns.
std::string failure_of(const ChildReading& reading, std::uint64_t address_space);

}  // namespace vdbmesh::detail
