#pragma once
// The one axis convention of the Python module (scikit-image's): array index (i, j, k) is
// voxel (x, y, z) = (k, j, i) of vdbmesh, so the last array axis is the fastest one of a
// scan file and slice z is a[z, :, :], contiguous in a C-ordered array. Spacing and
// vertices are in array axis order (i, j, k), as skimage.measure.marching_cubes has them.

#include <array>

#include "vdbmesh/read.h"

namespace vdbmesh::python {

/// Swaps the first and third columns of @a affine: turns an affine of array indices
/// (i, j, k) into one of voxels (x, y, z) = (k, j, i), and back.
Affine swap_i_and_k(const Affine& affine);

/// @a values per voxel axis (x, y, z) as values per array axis (i, j, k), or back.
template <typename T>
std::array<T, 3> reversed(const std::array<T, 3>& values) {
    return {values[2], values[1], values[0]};
}

}  // namespace vdbmesh::python
