#pragma once
// Helpers for the binary reader tests: files from bytes, gzip and zlib in memory, reading a
// whole (small) volume, and the world position of a voxel.

#include <zlib.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "vdbmesh/read.h"

namespace vdbmesh::test {

using Bytes = std::vector<unsigned char>;

inline void write_bytes(const std::filesystem::path& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

inline Bytes read_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline Bytes concat(Bytes a, const Bytes& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

inline Bytes text_bytes(const std::string& text) { return Bytes(text.begin(), text.end()); }

/// One gzip member (RFC 1952) holding @a data.
inline Bytes gzip_bytes(const Bytes& data) {
    z_stream z{};
    if (deflateInit2(&z, Z_BEST_SPEED, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
        throw std::runtime_error("deflateInit2");
    Bytes out(deflateBound(&z, data.size()) + 32);
    z.next_in = const_cast<unsigned char*>(data.data());
    z.avail_in = static_cast<unsigned>(data.size());
    z.next_out = out.data();
    z.avail_out = static_cast<unsigned>(out.size());
    const int status = deflate(&z, Z_FINISH);
    out.resize(z.total_out);
    deflateEnd(&z);
    if (status != Z_STREAM_END) throw std::runtime_error("deflate");
    return out;
}

/// A zlib-wrapped deflate stream (RFC 1950) holding @a data.
inline Bytes zlib_bytes(const Bytes& data) {
    uLongf size = compressBound(data.size());
    Bytes out(size);
    if (compress2(out.data(), &size, data.data(), data.size(), Z_BEST_SPEED) != Z_OK)
        throw std::runtime_error("compress2");
    out.resize(size);
    return out;
}

/// Reads every slice, @a slab slices at a time (the last slab may be shorter).
inline std::vector<float> read_all(VolumeReader& reader, std::int64_t slab = 3) {
    const VolumeHeader& h = reader.header();
    std::vector<float> values(static_cast<std::size_t>(h.voxel_count()));
    while (reader.next_slice() < h.dims[2]) {
        const std::int64_t count = std::min(slab, h.dims[2] - reader.next_slice());
        reader.read_slices(count, values.data() + reader.next_slice() * h.slice_voxels());
    }
    return values;
}

inline std::vector<float> read_all(VolumeSource source, std::int64_t slab = 3) {
    VolumeReader reader(std::move(source));
    return read_all(reader, slab);
}

/// The sample at voxel (x, y, z) of a volume read with read_all().
inline float voxel(const std::vector<float>& values, const VolumeHeader& h, std::int64_t x, std::int64_t y,
                   std::int64_t z) {
    return values.at(static_cast<std::size_t>((z * h.dims[1] + y) * h.dims[0] + x));
}

inline std::array<double, 3> world_of(const Affine& m, double i, double j, double k) {
    std::array<double, 3> w{};
    for (int r = 0; r < 3; ++r) w[r] = m[r][0] * i + m[r][1] * j + m[r][2] * k + m[r][3];
    return w;
}

}  // namespace vdbmesh::test
