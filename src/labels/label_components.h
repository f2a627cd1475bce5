#pragma once
// The closed pieces of each label's mesh and their signed volumes (private to src/labels): a
// piece can be turned inside out by smoothing without any crossing, so the hold-back compares
// each piece's volume sign with its unsmoothed one.

#include <array>
#include <cstdint>
#include <vector>

#include "vdbmesh/mesh.h"

namespace vdbmesh::labels_detail {

class LabelComponents {
public:
    /// Pieces of every non-background label's mesh: its triangles joined through shared vertices.
    LabelComponents(const Mesh& mesh, const std::vector<std::array<std::uint16_t, 2>>& sides);
    /// Signed volume of each piece at the mesh's present vertex positions (outward positive).
    std::vector<double> volumes(const Mesh& mesh) const;
    /// The vertices of pieces whose volume sign differs from @a reference's.
    std::vector<std::uint8_t> inverted(const Mesh& mesh, const std::vector<double>& reference) const;

private:
    std::vector<std::array<std::int32_t, 2>> piece_;  ///< per triangle and side: its piece, -1 for the background
    std::size_t pieces_ = 0;
};

}  // namespace vdbmesh::labels_detail
