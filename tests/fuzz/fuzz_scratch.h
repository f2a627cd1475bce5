#pragma once
// Scratch folder of the text-header fuzz targets. Their parsers never read a data file but
// do ask whether the files a header names exist and how long they are, so that a header can
// pass those checks a few small data files wait in a folder of the process's own:
//   data.raw         64 bytes (4x4x4 u8, 4x4x2 u16, 2x2x4 f32, 2x2x2 f64)
//   slice1.raw ...   16 bytes each, slice1.raw to slice4.raw (4x4 u8 per slice)
// and the input itself is written there as the header, for attached (LOCAL) data.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace vdbmesh::fuzz {

inline void write_file(const std::filesystem::path& path, const void* data, std::size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
}

/// The folder, made on first use and removed at exit.
class ScratchFolder {
public:
    ScratchFolder() : path_(std::filesystem::temp_directory_path() / ("vdbmesh-fuzz-" + std::to_string(::getpid()))) {
        std::filesystem::create_directories(path_);
        const std::string data(64, '\x01');
        write_file(path_ / "data.raw", data.data(), 64);
        for (int slice = 1; slice <= 4; ++slice)
            write_file(path_ / ("slice" + std::to_string(slice) + ".raw"), data.data(), 16);
    }
    ~ScratchFolder() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

inline const std::filesystem::path& scratch_dir() {
    static const ScratchFolder folder;
    return folder.path();
}

/// Writes the input as @a name in the scratch folder and returns its path.
inline std::filesystem::path write_header(const std::uint8_t* data, std::size_t size, const std::string& name) {
    const auto path = scratch_dir() / name;
    // A new file rather than a truncated one: ext4 flushes a file truncated and rewritten
    // on close (auto_da_alloc), which made every run wait for the disk.
    std::filesystem::remove(path);
    write_file(path, data, size);
    return path;
}

}  // namespace vdbmesh::fuzz
