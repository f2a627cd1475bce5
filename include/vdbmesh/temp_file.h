#pragma once
/// @file temp_file.h
/// @brief A temporary file for data larger than memory (the bounded `check`'s sorted runs, the
/// bricked mesher's spill), shared by the stages that need one.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace vdbmesh::detail {

/// A temporary file in $TMPDIR (or /tmp), unlinked as soon as it is made: it leaves nothing
/// behind, however the process ends. @a purpose ("for sorting") completes its error messages.
/// Held in memory instead when asked (a run with no memory limit: the kernel's copies into and
/// out of the page cache are then saved), the same bytes read back.
class TempFile {
public:
    enum class Held { on_disk, in_memory };
    /// @throw Error when no temporary file can be made.
    explicit TempFile(std::string purpose, Held held = Held::on_disk);
    ~TempFile();
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    /// Appends @a bytes. @throw Error when the disk is full.
    void append(const void* data, std::size_t bytes);
    /// Reads @a bytes at @a offset. @throw Error on a failed read.
    void read(std::uint64_t offset, void* data, std::size_t bytes) const;
    std::uint64_t size() const { return size_; }

private:
    void append_in_memory(const char* from, std::size_t bytes);
    void read_in_memory(std::uint64_t offset, char* to, std::size_t bytes) const;

    std::string purpose_;
    int fd_ = -1;  ///< none: held in memory, in chunks_
    std::vector<std::unique_ptr<char[]>> chunks_;
    std::uint64_t size_ = 0;
};

}  // namespace vdbmesh::detail
