#include "vdbmesh/atomic_file.h"

#include <limits.h>
#include <unistd.h>

#include <atomic>
#include <string>

#include "base/sync_to_disk.h"
#include "base/temporary_registry.h"
#include "vdbmesh/error.h"

namespace vdbmesh {

namespace {
/// Unique within the process; the pid makes it unique across processes.
std::string temp_suffix() {
    static std::atomic<unsigned> counter{0};
    return ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
}

/// The target's name shortened as needed so that name and suffix fit in one file name (NAME_MAX).
std::filesystem::path temp_name(const std::filesystem::path& target) {
    const std::string suffix = temp_suffix();
    std::string name = target.filename().string();
    const std::size_t longest = static_cast<std::size_t>(NAME_MAX) - suffix.size();
    if (name.size() > longest) name.resize(longest);
    return target.parent_path() / (name + suffix);
}
}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
    std::filesystem::path folder = target_.parent_path();
    if (folder.empty()) folder = ".";
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec))
        throw Error(target_.string() + ": output folder \"" + folder.string() + "\" does not exist");
    temp_ = temp_name(target_);
    signal_slot_ = detail::remember_temporary(temp_);
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    std::error_code ignored;
    std::filesystem::remove(temp_, ignored);
    detail::forget_temporary(signal_slot_);
}

void AtomicFile::commit() {
    detail::sync_to_disk(temp_, target_);
    std::error_code ec;
    std::filesystem::rename(temp_, target_, ec);
    if (ec) throw Error(target_.string() + ": cannot move the finished output into place (" + ec.message() + ")");
    committed_ = true;
    detail::forget_temporary(signal_slot_);
}

}  // namespace vdbmesh
