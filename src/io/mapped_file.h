#pragma once
// Private: a mesh file mapped read-only for read_mesh_records(), whose pages behind the reading
// are given back as it goes, so that a file of any size is read in a window of memory.

#include <cstddef>
#include <filesystem>

namespace vdbmesh::detail {

class MappedFile {
public:
    /// @throw FormatError when the file cannot be opened or mapped.
    explicit MappedFile(const std::filesystem::path& path);
    ~MappedFile();
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;

    const unsigned char* data() const { return data_; }
    std::size_t size() const { return size_; }
    /// Nothing before @a offset is read again: the pages wholly before it (less a margin, for
    /// a record that reaches back) leave memory once a window's worth has gathered.
    void release_before(std::size_t offset);

private:
    unsigned char* data_ = nullptr;
    std::size_t size_ = 0;
    std::size_t released_ = 0;  ///< bytes [0, released_) are given back
};

}  // namespace vdbmesh::detail
