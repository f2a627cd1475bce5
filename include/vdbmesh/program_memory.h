#pragma once
/// @file program_memory.h
/// @brief What every --memory plan counts besides its own work (issue 28).

#include <cstdint>

namespace vdbmesh {

/// The process itself, whatever the work: the program and its libraries (41 MB, the peak of
/// `vdbmesh --help`), the heap's and the threads' own, a mapped file's window (up to 9 MiB).
/// Set from the peak of a 33 M triangle PLY checked in 256M (bench/README.md, "Bounded check");
/// the bricked mesher, which counted 24 MiB, went 1.30x over a 152M limit on the bunny CT
/// (bench/README.md, "Scale", session 18).
inline constexpr std::uint64_t kProgramBytes = std::uint64_t(64) << 20;

/// The process's memory now (/proc/self/statm), bytes; zeros where it cannot be read.
struct ProcessMemory {
    std::uint64_t address_space = 0;  ///< what a forked child starts with
    std::uint64_t resident = 0;       ///< what a --memory plan measures as held
};
ProcessMemory process_memory_now();

}  // namespace vdbmesh
