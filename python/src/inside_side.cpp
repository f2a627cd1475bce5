#include "inside_side.h"

#include <array>
#include <cstdint>

#include "vdbmesh/error.h"

namespace vdbmesh::python {

namespace {

/// The side away from the border, from the samples on a box's faces: @a sample(x, y, z) for
/// x, y, z in [lo, hi] (inclusive), each face sample counted once.
template <typename Sample>
Inside side_of_border(const std::array<std::int64_t, 3>& lo, const std::array<std::int64_t, 3>& hi, double level,
                      const Sample& sample) {
    std::int64_t above = 0, below = 0;
    const auto vote = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
        const double value = sample(x, y, z);
        above += value > level;
        below += value < level;
    };
    for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
        for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
            if (z == lo[2] || z == hi[2] || y == lo[1] || y == hi[1]) {
                for (std::int64_t x = lo[0]; x <= hi[0]; ++x) vote(x, y, z);
            } else {
                vote(lo[0], y, z);
                if (hi[0] != lo[0]) vote(hi[0], y, z);
            }
        }
    return above > below ? Inside::below : Inside::above;
}

template <typename T>
double array_sample(const StridedVolume& v, std::int64_t i, std::int64_t j, std::int64_t k) {
    const char* at = static_cast<const char*>(v.data) + i * v.strides[0] + j * v.strides[1] + k * v.strides[2];
    return double(*reinterpret_cast<const T*>(at));
}

using ArraySample = double (*)(const StridedVolume&, std::int64_t, std::int64_t, std::int64_t);

ArraySample array_sample_of(SampleType type) {
    switch (type) {
        case SampleType::u8: return array_sample<std::uint8_t>;
        case SampleType::i8: return array_sample<std::int8_t>;
        case SampleType::u16: return array_sample<std::uint16_t>;
        case SampleType::i16: return array_sample<std::int16_t>;
        case SampleType::u32: return array_sample<std::uint32_t>;
        case SampleType::i32: return array_sample<std::int32_t>;
        case SampleType::f32: return array_sample<float>;
        case SampleType::f64: return array_sample<double>;
    }
    throw Error("internal: unknown sample type");
}

}  // namespace

Inside inside_away_from_border(const openvdb::FloatGrid& grid, double level) {
    const auto box = stored_scan_box(grid);
    if (!box) {
        if (grid.getGridClass() == openvdb::GRID_LEVEL_SET) return Inside::below;
        return grid.background() > level ? Inside::below : Inside::above;
    }
    auto accessor = grid.getConstAccessor();
    const openvdb::Coord lo = box->min(), hi = box->max();
    return side_of_border({lo.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), hi.z()}, level,
                          [&](std::int64_t x, std::int64_t y, std::int64_t z) {
                              return accessor.getValue(openvdb::Coord(int(x), int(y), int(z)));
                          });
}

Inside inside_away_from_border(const StridedVolume& volume, double level) {
    // Array index (i, j, k) is voxel (x, y, z) = (k, j, i) (axis_order.h).
    const ArraySample sample = array_sample_of(volume.type);
    return side_of_border({0, 0, 0}, {volume.shape[2] - 1, volume.shape[1] - 1, volume.shape[0] - 1}, level,
                          [&](std::int64_t x, std::int64_t y, std::int64_t z) { return sample(volume, z, y, x); });
}

}  // namespace vdbmesh::python
