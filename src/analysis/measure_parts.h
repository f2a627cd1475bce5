#pragma once
// Private: the parts of measure_mesh() (measure_mesh.cpp) the bounded measure shares
// (measure_stream.cpp).

#include <array>
#include <vector>

#include "vdbmesh/measure.h"

namespace vdbmesh::detail {

/// measure.principal_moments and principal_axes from @a inertia.
void set_principal_frame(const std::array<std::array<double, 3>, 3>& inertia, MeshMeasure& measure);

/// Largest |volume| first (ties: larger area first; further ties keep their order).
void sort_components(std::vector<ComponentMeasure>& components);

}  // namespace vdbmesh::detail
