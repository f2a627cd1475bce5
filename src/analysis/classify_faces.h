#pragma once
// Private: validity of a mesh's indices and the degenerate faces every analysis skips.

#include <cstdint>
#include <vector>

#include "vdbmesh/mesh.h"

namespace vdbmesh::detail {

enum class FaceClass : std::uint8_t {
    kRegular,         ///< three distinct, non-collinear corners
    kRepeatedVertex,  ///< an index used twice
    kZeroArea,        ///< distinct indices, exactly collinear (or coincident) corners
};

/// Throws Error when a triangle refers to a vertex that does not exist.
void check_indices(const Mesh& mesh);

/// One class per triangle, decided with exact predicates (parallel, deterministic).
std::vector<FaceClass> classify_faces(const Mesh& mesh);

/// Indices of the regular triangles, in increasing order.
std::vector<std::uint32_t> regular_faces(const std::vector<FaceClass>& classes);

}  // namespace vdbmesh::detail
