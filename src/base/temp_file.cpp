// TempFile (temp_file.h): mkstemp(3) in $TMPDIR or /tmp, unlinked at once; written and read with
// write(2) and pread(2), every short count retried and every failure named. Or held in memory,
// in chunks that never move.
#include "vdbmesh/temp_file.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>

#include "vdbmesh/error.h"

namespace vdbmesh::detail {
namespace {

/// Bytes of one chunk of a file held in memory: allocated as the file grows (untouched pages
/// of the last cost nothing), never moved.
constexpr std::size_t kChunkBytes = std::size_t{8} << 20;

std::string temp_folder() {
    const char* folder = std::getenv("TMPDIR");
    return folder && *folder ? folder : "/tmp";
}

}  // namespace

TempFile::TempFile(std::string purpose, Held held) : purpose_(std::move(purpose)) {
    if (held == Held::in_memory) return;
    std::string name = temp_folder() + "/vdbmesh-XXXXXX";
    fd_ = ::mkstemp(name.data());
    if (fd_ < 0) throw Error(name + ": cannot make a temporary file " + purpose_ + ": " + std::strerror(errno));
    ::unlink(name.c_str());
}

TempFile::~TempFile() {
    if (fd_ >= 0) ::close(fd_);
}

void TempFile::append(const void* data, std::size_t bytes) {
    const char* from = static_cast<const char*>(data);
    if (fd_ < 0) return append_in_memory(from, bytes);
    while (bytes > 0) {
        const ssize_t done = ::pwrite(fd_, from, bytes, off_t(size_));
        if (done < 0 && errno == EINTR) continue;
        if (done <= 0) {
            throw Error(temp_folder() + ": cannot write the temporary file " + purpose_ + " (" + std::strerror(errno) +
                        "; TMPDIR chooses where it goes)");
        }
        from += done, bytes -= std::size_t(done), size_ += std::uint64_t(done);
    }
}

void TempFile::read(std::uint64_t offset, void* data, std::size_t bytes) const {
    char* to = static_cast<char*>(data);
    if (fd_ < 0) return read_in_memory(offset, to, bytes);
    while (bytes > 0) {
        const ssize_t done = ::pread(fd_, to, bytes, off_t(offset));
        if (done < 0 && errno == EINTR) continue;
        if (done <= 0) throw Error(temp_folder() + ": cannot read back the temporary file " + purpose_ + ": " + std::strerror(errno));
        to += done, bytes -= std::size_t(done), offset += std::uint64_t(done);
    }
}

void TempFile::append_in_memory(const char* from, std::size_t bytes) {
    while (bytes > 0) {
        const std::size_t at = std::size_t(size_ % kChunkBytes);
        if (at == 0) chunks_.push_back(std::unique_ptr<char[]>(new char[kChunkBytes]));
        const std::size_t taken = std::min(bytes, kChunkBytes - at);
        std::memcpy(chunks_.back().get() + at, from, taken);
        from += taken, bytes -= taken, size_ += taken;
    }
}

void TempFile::read_in_memory(std::uint64_t offset, char* to, std::size_t bytes) const {
    if (offset + bytes > size_) throw Error("the temporary data " + purpose_ + " holds less than is read back");
    while (bytes > 0) {
        const std::size_t at = std::size_t(offset % kChunkBytes);
        const std::size_t taken = std::min(bytes, kChunkBytes - at);
        std::memcpy(to, chunks_[std::size_t(offset / kChunkBytes)].get() + at, taken);
        to += taken, bytes -= taken, offset += taken;
    }
}

}  // namespace vdbmesh::detail
