#include "array_slice_reader.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <utility>

#include "axis_order.h"
#include "vdbmesh/error.h"

namespace vdbmesh::python {

namespace {

/// Whether no value is a NaN or an infinity (exponent bits all set), tested on the bits so that it vectorises.
bool all_finite(const float* values, std::int64_t n) {
    std::uint32_t bad = 0;
    for (std::int64_t i = 0; i < n; ++i) {
        std::uint32_t bits;
        std::memcpy(&bits, values + i, sizeof bits);
        bad |= (bits & 0x7f800000u) == 0x7f800000u;
    }
    return bad == 0;
}

/// Converts row [z, y, :] of the array to floats; returns whether they are all finite.
template <typename T>
bool convert_row(const StridedVolume& v, std::int64_t z, std::int64_t y, float* out) {
    const char* row = static_cast<const char*>(v.data) + z * v.strides[0] + y * v.strides[1];
    const std::int64_t width = v.shape[2];
    if (v.strides[2] == static_cast<std::int64_t>(sizeof(T))) {  // contiguous: let the compiler vectorise
        const T* samples = reinterpret_cast<const T*>(row);
        for (std::int64_t x = 0; x < width; ++x) out[x] = static_cast<float>(samples[x]);
    } else {
        for (std::int64_t x = 0; x < width; ++x)
            out[x] = static_cast<float>(*reinterpret_cast<const T*>(row + x * v.strides[2]));
    }
    if constexpr (std::is_floating_point_v<T>) return all_finite(out, width);
    return true;
}

/// Converts slices [first, first + count) of the array to floats, all rows in one parallel
/// loop; returns whether they are all finite.
template <typename T>
bool convert_slices(const StridedVolume& v, std::int64_t first, std::int64_t count, float* out) {
    const std::int64_t height = v.shape[1], width = v.shape[2];
    std::atomic<bool> finite{true};
    tbb::parallel_for(std::int64_t{0}, count * height, [&](std::int64_t row) {
        if (!convert_row<T>(v, first + row / height, row % height, out + row * width))
            finite.store(false, std::memory_order_relaxed);
    });
    return finite.load();
}

bool convert_slices(const StridedVolume& v, std::int64_t first, std::int64_t count, float* out) {
    switch (v.type) {
        case SampleType::u8: return convert_slices<std::uint8_t>(v, first, count, out);
        case SampleType::i8: return convert_slices<std::int8_t>(v, first, count, out);
        case SampleType::u16: return convert_slices<std::uint16_t>(v, first, count, out);
        case SampleType::i16: return convert_slices<std::int16_t>(v, first, count, out);
        case SampleType::u32: return convert_slices<std::uint32_t>(v, first, count, out);
        case SampleType::i32: return convert_slices<std::int32_t>(v, first, count, out);
        case SampleType::f32: return convert_slices<float>(v, first, count, out);
        case SampleType::f64: return convert_slices<double>(v, first, count, out);
    }
    throw Error("internal: unknown sample type");
}

}  // namespace

ArraySliceReader::ArraySliceReader(const StridedVolume& volume, const Affine& array_to_world, std::string name)
    : volume_(volume) {
    header_.format = "array";
    header_.path = std::move(name);
    header_.dims = reversed(volume.shape);
    header_.type = volume.type;
    header_.index_to_world = swap_i_and_k(array_to_world);
    for (int axis = 0; axis < 3; ++axis) {
        const auto& m = header_.index_to_world;
        header_.spacing[axis] = std::sqrt(m[0][axis] * m[0][axis] + m[1][axis] * m[1][axis] + m[2][axis] * m[2][axis]);
    }
}

void ArraySliceReader::read_slices(std::int64_t slices, float* out) {
    if (slices < 0 || next_slice_ + slices > volume_.shape[0]) throw Error("internal: read_slices past the last slice");
    if (!convert_slices(volume_, next_slice_, slices, out)) throw_not_finite(out, slices);
    next_slice_ += slices;
}

void ArraySliceReader::throw_not_finite(const float* values, std::int64_t slices) const {
    const std::int64_t count = header_.slice_voxels() * slices;
    const float* bad = std::find_if(values, values + count, [](float v) { return !std::isfinite(v); });
    const std::int64_t index = bad - values;
    const std::int64_t z = next_slice_ + index / header_.slice_voxels();
    const std::int64_t y = (index / volume_.shape[2]) % volume_.shape[1], x = index % volume_.shape[2];
    throw FormatError(header_.path.string(),
                      "sample [" + std::to_string(z) + ", " + std::to_string(y) + ", " + std::to_string(x) + "]",
                      "a finite number", std::isnan(*bad) ? "NaN" : "infinity (or beyond the float range)");
}

}  // namespace vdbmesh::python
