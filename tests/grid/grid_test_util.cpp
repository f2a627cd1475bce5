#include "grid_test_util.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <limits>

namespace vdbmesh::test {

DenseVolume make_volume(const Dims& dims, const std::function<float(int, int, int)>& field) {
    DenseVolume volume{dims, {}};
    volume.values.reserve(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2]);
    for (int z = 0; z < dims[2]; ++z)
        for (int y = 0; y < dims[1]; ++y)
            for (int x = 0; x < dims[0]; ++x) volume.values.push_back(field(x, y, z));
    return volume;
}

std::unique_ptr<VolumeReader> write_and_open(const DenseVolume& volume, const std::filesystem::path& path) {
    {
        std::ofstream out(path, std::ios::binary);
        out.write(reinterpret_cast<const char*>(volume.values.data()),
                  static_cast<std::streamsize>(volume.values.size() * sizeof(float)));
    }
    ReadOptions options;
    options.raw_dims = std::array<std::int64_t, 3>{volume.dims[0], volume.dims[1], volume.dims[2]};
    options.raw_type = SampleType::f32;
    options.raw_byte_order = ByteOrder::little;
    return open_volume(path, options);
}

ReferenceBand::ReferenceBand(const DenseVolume& volume, double lo, double hi, int band)
    : dims_(volume.dims), pad_(band + 1) {
    active_.assign(static_cast<std::size_t>(dims_[0] + 2 * pad_) * (dims_[1] + 2 * pad_) * (dims_[2] + 2 * pad_), 0);
    const double virtual_sample = -std::numeric_limits<double>::infinity();
    auto sample = [&](int x, int y, int z) { return volume.contains(x, y, z) ? volume.at(x, y, z) : virtual_sample; };
    for (int z = -1; z < dims_[2]; ++z)
        for (int y = -1; y < dims_[1]; ++y)
            for (int x = -1; x < dims_[0]; ++x) {
                double min = std::numeric_limits<double>::infinity(), max = -min;
                for (int c = 0; c < 8; ++c) {
                    const double v = sample(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2));
                    min = std::min(min, v);
                    max = std::max(max, v);
                }
                if (!(min < max && min <= hi && max > lo)) continue;
                for (int c = 0; c < 8; ++c) {
                    const int cx = x + (c & 1), cy = y + ((c >> 1) & 1), cz = z + (c >> 2);
                    for (int dz = -band; dz <= band; ++dz)
                        for (int dy = -band; dy <= band; ++dy)
                            for (int dx = -band; dx <= band; ++dx)
                                if (std::abs(dx) + std::abs(dy) + std::abs(dz) <= band)
                                    active_[index(cx + dx, cy + dy, cz + dz)] = 1;
                }
            }
}

std::size_t ReferenceBand::index(int x, int y, int z) const {
    return static_cast<std::size_t>(x + pad_) +
           static_cast<std::size_t>(dims_[0] + 2 * pad_) *
               (static_cast<std::size_t>(y + pad_) + static_cast<std::size_t>(dims_[1] + 2 * pad_) * (z + pad_));
}

bool ReferenceBand::active(int x, int y, int z) const {
    if (x < -pad_ || y < -pad_ || z < -pad_ || x >= dims_[0] + pad_ || y >= dims_[1] + pad_ || z >= dims_[2] + pad_)
        return false;
    return active_[index(x, y, z)] != 0;
}

}  // namespace vdbmesh::test
