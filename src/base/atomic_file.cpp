#include "vdbmesh/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <string>

#include "vdbmesh/error.h"

namespace vdbmesh {

namespace {
/// Unique within the process; the pid makes it unique across processes.
std::string temp_suffix() {
    static std::atomic<unsigned> counter{0};
    return ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
}
}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
    std::filesystem::path folder = target_.parent_path();
    if (folder.empty()) folder = ".";
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec))
        throw Error(target_.string() + ": output folder \"" + folder.string() + "\" does not exist");
    temp_ = target_;
    temp_ += temp_suffix();
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    std::error_code ignored;
    std::filesystem::remove(temp_, ignored);
}

void AtomicFile::commit() {
    std::error_code ec;
    std::filesystem::rename(temp_, target_, ec);
    if (ec) throw Error(target_.string() + ": cannot move the finished output into place (" + ec.message() + ")");
    committed_ = true;
}

}  // namespace vdbmesh
