// MappedFile: mmap(2) of a whole mesh file, read-only and private; madvise(MADV_DONTNEED) on
// the pages read (they are the file's: touched again, they are read again, never lost), so the
// resident part stays within a window whatever the file's size.
#include "io/mapped_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "io/mesh_io_detail.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {
namespace {

constexpr std::size_t kWindowBytes = std::size_t(8) << 20;  // given back in steps of this much
constexpr std::size_t kMarginBytes = std::size_t(1) << 20;  // kept behind the reading

}  // namespace

MappedFile::MappedFile(const std::filesystem::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw FormatError(path.string(), "cannot open the file: " + std::string(std::strerror(errno)));
    struct stat status {};
    if (::fstat(fd, &status) != 0 || !S_ISREG(status.st_mode)) {
        ::close(fd);
        throw FormatError(path.string(), "file", "a regular file", "something else");
    }
    size_ = std::size_t(status.st_size);
    if (size_ > 0) {
        void* address = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
        if (address == MAP_FAILED) {
            const std::string reason = std::strerror(errno);
            ::close(fd);
            throw FormatError(path.string(), "cannot map the file: " + reason);
        }
        data_ = static_cast<unsigned char*>(address);
        ::madvise(address, size_, MADV_SEQUENTIAL);
    }
    ::close(fd);  // the mapping keeps the file
}

MappedFile::~MappedFile() {
    if (data_) ::munmap(data_, size_);
}

void MappedFile::release_before(std::size_t offset) {
    if (offset < released_ + kWindowBytes + kMarginBytes) return;
    const std::size_t page = std::size_t(::sysconf(_SC_PAGESIZE));
    const std::size_t end = (offset - kMarginBytes) / page * page;
    ::madvise(data_ + released_, end - released_, MADV_DONTNEED);
    released_ = end;
}

void ByteView::done_before(std::size_t offset) const {
    if (mapping_) mapping_->release_before(offset);
}

}  // namespace vdbmesh::detail
