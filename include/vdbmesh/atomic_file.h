#pragma once
/// @file atomic_file.h
/// @brief Outputs are written to a temporary file beside the target and renamed over it
/// only when complete, so a failed run never leaves a half-written file or clobbers a good one.

#include <filesystem>

namespace vdbmesh {

/// A temporary path next to @a target; commit() renames it onto the target, and the
/// destructor deletes it when commit() was not reached (an exception, a failed check).
/// SIGINT, SIGTERM and SIGHUP delete it too (see base/temporary_registry.h). The temporary's
/// name is the target's, shortened when needed, plus ".tmp-<pid>-<n>", so any valid target
/// name works.
class AtomicFile {
public:
    explicit AtomicFile(std::filesystem::path target);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    /// Where to write. Throws Error when the target's folder does not exist.
    const std::filesystem::path& temp_path() const { return temp_; }
    /// Flushes the temporary file (or folder) to disk with fsync, then renames it onto the
    /// target. Throws Error on failure; the target is then left as it was.
    void commit();

private:
    std::filesystem::path target_;
    std::filesystem::path temp_;
    bool committed_ = false;
    int signal_slot_ = -1;
};

}  // namespace vdbmesh
