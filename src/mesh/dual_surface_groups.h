#pragma once
// Private: the edge groups of a Marching Cubes cell, for the dual surface (dual_surface.cpp):
// the polygons mc_case() triangulates, one group of crossed edges each, so that a cell gets
// one vertex per polygon (several where a face or the cell is ambiguous).

#include <array>
#include <cstdint>

namespace vdbmesh::detail {

/// The groups of one corner configuration (bit c set when corner c is inside).
struct CellGroups {
    std::uint8_t count = 0;
    /// The group (0 .. count - 1) of each cell edge (kEdgeCorners), -1 where the edge is not crossed.
    std::array<std::int8_t, 12> of_edge{};
    /// Each crossed edge's place among its group's edges (in edge order): its quad's slot in
    /// the star of the group's vertex.
    std::array<std::uint8_t, 12> rank{};
    std::array<std::uint8_t, 4> size{};  ///< each group's crossed edges
};

/// The groups for configuration @a config (0..255): the edges of mc_case(config)'s triangles,
/// joined where two triangles share an edge.
const CellGroups& cell_groups(unsigned config);

/// The cell edge (0..11) from corner @a corner (0..7) along @a axis (0..2); the corner is the
/// edge's lower end.
int cell_edge(unsigned corner, int axis);

}  // namespace vdbmesh::detail
