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

/// CPU seconds a child may use to read @a bytes of a sound file: generous (a sound file reads
/// at hundreds of MB/s), yet a reader that loops on a corrupt one is stopped within seconds.
/// CPU time, not wall time: a healthy read starved of the cores by other work is not refused.
unsigned reading_cpu_seconds(std::uintmax_t bytes);

/// Wall seconds after which a child that has not finished is taken as blocked (a lock another
/// thread of the parent held at fork(): it waits without using CPU). Much longer than
/// @a cpu_seconds: only a child that is not reading at all should reach it.
unsigned blocked_wall_seconds(unsigned cpu_seconds);

/// What a reading child may use before it is stopped.
struct ChildLimits {
    std::uint64_t address_space = 0;  ///< bytes (RLIMIT_AS)
    unsigned cpu_seconds = 1;         ///< RLIMIT_CPU: a reader that loops
    unsigned wall_seconds = 1;        ///< an alarm: a child blocked without using CPU
};

/// Runs @a reading in a forked child within @a limits; throws FormatError naming @a path when
/// it crashes, throws, runs out of memory or CPU time, or is still blocked after the wall
/// limit twice (a second child is forked at another moment, see the definition).
void run_in_child(const std::filesystem::path& path, const ChildReading& reading, const ChildLimits& limits);

/// The text of the FormatError for a child stopped by its CPU limit / its wall limit.
std::string cpu_limit_failure(unsigned cpu_seconds);
std::string blocked_failure(unsigned wall_seconds);

/// Lets this (child) process use @a seconds more CPU time before SIGXCPU ends it.
void limit_cpu_from_now(unsigned seconds);


/// Prepares a freshly forked reading child: default signal handlers (SIGXCPU's included), no
/// core file, at most @a address_space bytes of address space, stderr to /dev/null (glibc's and
/// OpenVDB's own complaints).
void enter_reading_child(std::uint64_t address_space);

/// The text a reading child reports when @a reading throws, empty when it returns.
std::string failure_of(const ChildReading& reading, std::uint64_t address_space);

}  // namespace vdbmesh::detail
