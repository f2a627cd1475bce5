// process_memory_now() (program_memory.h): /proc/self/statm's first two fields, in pages.

#include <unistd.h>

#include <cstdio>

#include "vdbmesh/program_memory.h"

namespace vdbmesh {

ProcessMemory process_memory_now() {
    unsigned long size = 0, resident = 0;
    if (std::FILE* statm = std::fopen("/proc/self/statm", "r")) {
        if (std::fscanf(statm, "%lu %lu", &size, &resident) != 2) size = resident = 0;
        std::fclose(statm);
    }
    const auto page = std::uint64_t(::sysconf(_SC_PAGESIZE));
    return {std::uint64_t(size) * page, std::uint64_t(resident) * page};
}

}  // namespace vdbmesh
