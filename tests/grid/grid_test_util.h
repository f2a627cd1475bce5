#pragma once
// Helpers of the grid tests: small float volumes written as headerless raw files and read back
// through the raw reader, and a brute-force reference for the active band.

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include "vdbmesh/read.h"

namespace vdbmesh::test {

using Dims = std::array<int, 3>;

/// A dense volume, x fastest.
struct DenseVolume {
    Dims dims{};
    std::vector<float> values;
    float at(int x, int y, int z) const {
        return values[static_cast<std::size_t>(x) + static_cast<std::size_t>(dims[0]) * (y + static_cast<std::size_t>(dims[1]) * z)];
    }
    bool contains(int x, int y, int z) const {
        return x >= 0 && y >= 0 && z >= 0 && x < dims[0] && y < dims[1] && z < dims[2];
    }
};

/// Samples @a field at every voxel.
DenseVolume make_volume(const Dims& dims, const std::function<float(int, int, int)>& field);

/// Writes @a volume as little-endian f32 raw and opens it with the raw reader.
std::unique_ptr<VolumeReader> write_and_open(const DenseVolume& volume, const std::filesystem::path& path);

/// The voxels the converter must activate: corners of cells whose samples (outside the scan:
/// below every isovalue) have min <= iso < max for some iso in [lo, hi], dilated by @a band in
/// the L1 metric. Indexed over [-band - 1, dim + band] per axis.
class ReferenceBand {
public:
    ReferenceBand(const DenseVolume& volume, double lo, double hi, int band);
    bool active(int x, int y, int z) const;

private:
    Dims dims_;
    int pad_;
    std::vector<std::uint8_t> active_;
    std::size_t index(int x, int y, int z) const;
};

}  // namespace vdbmesh::test
