// SliceReader's default read of a part of each slice (read.h).

#include <algorithm>
#include <string>
#include <vector>

#include "formats.h"
#include "vdbmesh/error.h"
#include "vdbmesh/read.h"

namespace vdbmesh {

namespace detail {

void check_slice_part(const VolumeHeader& header, const SliceRectangle& part) {
    const bool inside = part.min_x >= 0 && part.min_y >= 0 && part.width > 0 && part.height > 0 &&
                        part.min_x + part.width <= header.dims[0] && part.min_y + part.height <= header.dims[1];
    if (!inside)
        throw Error("internal: slice part at (" + std::to_string(part.min_x) + ", " + std::to_string(part.min_y) + ") of " +
                    std::to_string(part.width) + " x " + std::to_string(part.height) + " outside a slice of " +
                    std::to_string(header.dims[0]) + " x " + std::to_string(header.dims[1]));
}

}  // namespace detail

void SliceReader::read_slice_part(std::int64_t slices, const SliceRectangle& part, float* out) {
    const VolumeHeader& h = header();
    detail::check_slice_part(h, part);
    std::vector<float> slice(static_cast<std::size_t>(h.slice_voxels()));
    for (std::int64_t s = 0; s < slices; ++s) {
        read_slices(1, slice.data());
        for (std::int64_t y = 0; y < part.height; ++y) {
            const float* row = slice.data() + (part.min_y + y) * h.dims[0] + part.min_x;
            std::copy_n(row, part.width, out + (s * part.height + y) * part.width);
        }
    }
}

}  // namespace vdbmesh
