#pragma once
/// @file checked_output.h
/// @brief An output file written through a std::ostream whose every failure is caught.

#include <filesystem>
#include <fstream>
#include <ostream>

#include "vdbmesh/atomic_file.h"

namespace vdbmesh {

/// A binary std::ofstream on an AtomicFile. Write to stream(); commit() flushes and closes it,
/// throws Error naming the target if any write failed (a full disk, a file size limit), and
/// otherwise syncs and renames the file into place. Without commit() the target is untouched.
class CheckedOutput {
public:
    /// Throws Error when the temporary file cannot be created.
    explicit CheckedOutput(std::filesystem::path target);

    std::ostream& stream() { return out_; }
    void commit();

private:
    std::filesystem::path target_;
    AtomicFile file_;
    std::ofstream out_;
};

}  // namespace vdbmesh
