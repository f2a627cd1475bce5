#pragma once
// A SliceReader over an array in memory (a numpy buffer, any strides): convert_to_grid()
// streams the array itself, one slice at a time, converting samples to float as it goes.

#include <array>
#include <cstdint>
#include <string>

#include "vdbmesh/read.h"

namespace vdbmesh::python {

/// A 3D array in memory: element [i, j, k] lies at data + i * strides[0] + j * strides[1]
/// + k * strides[2] bytes (numpy's layout; strides may be negative).
struct StridedVolume {
    const void* data = nullptr;
    SampleType type = SampleType::f32;
    std::array<std::int64_t, 3> shape{};
    std::array<std::int64_t, 3> strides{};
};

/// Hands out array[z, y, x] as voxel (x, y, z) (axis_order.h). Throws FormatError naming
/// the array index of the first NaN or infinity.
class ArraySliceReader final : public SliceReader {
public:
    /// @a array_to_world maps array indices (i, j, k) to the world; @a name stands for the
    /// array in error messages.
    ArraySliceReader(const StridedVolume& volume, const Affine& array_to_world, std::string name);

    const VolumeHeader& header() const override { return header_; }
    void read_slices(std::int64_t slices, float* out) override;
    std::int64_t next_slice() const override { return next_slice_; }

private:
    /// Throws the FormatError for the first NaN or infinity of @a values, the next @a slices slices.
    [[noreturn]] void throw_not_finite(const float* values, std::int64_t slices) const;

    StridedVolume volume_;
    VolumeHeader header_;
    std::int64_t next_slice_ = 0;
};

}  // namespace vdbmesh::python
