// TempFile (temp_file.h): mkstemp(3) in $TMPDIR or /tmp, unlinked at once; written and read with
// write(2) and pread(2), every short count retried and every failure named.
#include "vdbmesh/temp_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>

#include "vdbmesh/error.h"

namespace vdbmesh::detail {
namespace {

std::string temp_folder() {
    const char* folder = std::getenv("TMPDIR");
    return folder && *folder ? folder : "/tmp";
}

}  // namespace

TempFile::TempFile(std::string purpose) : purpose_(std::move(purpose)) {
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
    while (bytes > 0) {
        const ssize_t done = ::pread(fd_, to, bytes, off_t(offset));
        if (done < 0 && errno == EINTR) continue;
        if (done <= 0) throw Error(temp_folder() + ": cannot read back the temporary file " + purpose_ + ": " + std::strerror(errno));
        to += done, bytes -= std::size_t(done), offset += std::uint64_t(done);
    }
}

}  // namespace vdbmesh::detail
