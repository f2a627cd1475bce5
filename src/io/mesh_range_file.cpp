// A mesh file several ranks write together (mesh_range_file.h).

#include "vdbmesh/mesh_range_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "vdbmesh/error.h"

namespace vdbmesh {

MeshRangeFile::MeshRangeFile(std::filesystem::path target, bool ascii) : target_(std::move(target)), format_(target_, ascii) {}

MeshRangeFile::~MeshRangeFile() {
    if (descriptor_ >= 0) ::close(descriptor_);
}

std::string MeshRangeFile::header(std::uint64_t vertex_count, std::uint64_t triangle_count) {
    return format_.header(vertex_count, triangle_count);
}

std::string MeshRangeFile::footer() const { return format_.footer(); }

void MeshRangeFile::vertices(const std::vector<std::array<float, 3>>& positions, std::string& out) const { format_.vertices(positions, out); }

void MeshRangeFile::triangles(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                              const std::vector<std::array<std::array<float, 3>, 3>>& corners, std::string& out) const {
    format_.triangles(triangles, corners, out);
}

std::string MeshRangeFile::open(const std::string& made) {
    std::string path = made;
    if (made.empty()) {
        made_.emplace(target_);
        path = made_->temp_path().string();
    }
    descriptor_ = ::open(path.c_str(), made.empty() ? O_WRONLY | O_CREAT | O_TRUNC : O_WRONLY, 0666);
    if (descriptor_ < 0) throw Error(target_.string() + ": cannot open " + path + " to write the mesh: " + std::strerror(errno));
    return path;
}

void MeshRangeFile::write_at(std::uint64_t offset, const char* bytes, std::size_t count) {
    while (count > 0) {
        const ssize_t written = ::pwrite(descriptor_, bytes, count, off_t(offset));
        if (written < 0 && errno == EINTR) continue;
        if (written <= 0) throw Error(target_.string() + ": cannot write the mesh: " + std::strerror(errno));
        bytes += written, offset += std::uint64_t(written), count -= std::size_t(written);
    }
}

void MeshRangeFile::close(bool commit) {
    const bool closed = descriptor_ < 0 || ::close(descriptor_) == 0;
    descriptor_ = -1;
    if (!made_) return;
    if (commit && closed) {
        made_->commit();
    } else {
        made_.reset();  // removes the temporary file
        if (commit) throw Error(target_.string() + ": cannot close the mesh file: " + std::strerror(errno));
    }
}

}  // namespace vdbmesh
