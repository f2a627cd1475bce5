#pragma once
/// @file temp_file.h
/// @brief A temporary file for data larger than memory (the bounded `check`'s sorted runs, the
/// bricked mesher's spill), shared by the stages that need one.

#include <cstddef>
#include <cstdint>
#include <string>

namespace vdbmesh::detail {

/// A temporary file in $TMPDIR (or /tmp), unlinked as soon as it is made: it leaves nothing
/// behind, however the process ends. @a purpose ("for sorting") completes its error messages.
class TempFile {
public:
    /// @throw Error when no temporary file can be made.
    explicit TempFile(std::string purpose);
    ~TempFile();
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    /// Appends @a bytes. @throw Error when the disk is full.
    void append(const void* data, std::size_t bytes);
    /// Reads @a bytes at @a offset. @throw Error on a failed read.
    void read(std::uint64_t offset, void* data, std::size_t bytes) const;
    std::uint64_t size() const { return size_; }

private:
    std::string purpose_;
    int fd_ = -1;
    std::uint64_t size_ = 0;
};

}  // namespace vdbmesh::detail
