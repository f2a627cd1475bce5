#include "axis_order.h"

#include <utility>

namespace vdbmesh::python {

Affine swap_i_and_k(const Affine& affine) {
    Affine swapped = affine;
    for (auto& row : swapped) std::swap(row[0], row[2]);
    return swapped;
}

}  // namespace vdbmesh::python
