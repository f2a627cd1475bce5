#include "base/sync_to_disk.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

void sync_one(const std::filesystem::path& path, const std::filesystem::path& name) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    const bool synced = fd >= 0 && ::fsync(fd) == 0;
    const int error = errno;
    if (fd >= 0) ::close(fd);
    if (!synced)
        throw Error(name.string() + ": cannot flush the written data to disk (" + std::strerror(error) + ")");
}

}  // namespace

void sync_to_disk(const std::filesystem::path& path, const std::filesystem::path& name) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        for (const auto& entry : std::filesystem::directory_iterator(path)) {
            if (entry.is_regular_file()) sync_one(entry.path(), name);
        }
    }
    sync_one(path, name);
}

}  // namespace vdbmesh::detail
