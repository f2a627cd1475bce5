#pragma once
// Private: the dual surface's quads with their diagonals, and the proof that no two of its
// triangles cross (dual_surface_proof.cpp says why the proof is complete).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh/dual_surface_cells.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::detail {

/// Where each vertex is: the written coordinates (world space, float, held as double), and
/// those of its fallback, the mean of its crossings.
struct DualPositions {
    std::vector<Point3> at;
    std::vector<Point3> mean;
    std::vector<bool> at_mean;  ///< the vertex was moved to its mean by the proof
    /// Per quad: split along its diagonal 1-3 (else 0-2), the one whose two triangles have the
    /// larger smallest angle.
    std::vector<std::uint8_t> split_13;
};

/// Chooses every quad's diagonal (DualPositions::split_13) at the vertices' positions.
void choose_splits(const DualCells& cells, DualPositions& positions);

/// What the proof did.
struct DualProofFigures {
    std::size_t cells = 0;           ///< cells with surface
    std::size_t certified = 0;       ///< of them, cleared by the projection certificate
    std::size_t pairs_tested = 0;    ///< triangle pairs given exact tests
    std::size_t pairs_failed = 0;    ///< of them, found meeting (every round)
    std::size_t moved = 0;           ///< vertices moved back to their crossings' mean
    std::size_t unresolved = 0;      ///< pairs still meeting with every vertex at its mean
    int rounds = 0;
};

/// Proves that no two triangles of the surface meet beyond the edges and corners they share;
/// where two do, moves their vertices to their crossings' means and proves the cells round
/// them again, until none meet or every such vertex is at its mean (then counted unresolved).
/// The first round's time goes to @a report's phase "proof", the later rounds' to "fallback".
DualProofFigures prove_no_crossings(const DualCells& cells, DualPositions& positions, MeshReport& report);

}  // namespace vdbmesh::detail
