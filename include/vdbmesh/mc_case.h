#pragma once
/// @file mc_case.h
/// @brief The Marching Cubes case table of the mesh stage (mc_table.cpp), for the stages that
/// march cubes themselves and must make exactly mesh_grid(MeshMethod::mc)'s triangles (the
/// shared tree's memoised Marching Cubes). vdbmesh::detail: shared between stages, not a
/// stable API. OpenVDB-free.

#include <array>
#include <cstdint>

namespace vdbmesh::detail {

/// Corner c of a cell sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1) from its minimum corner.
/// Edge e joins corners kEdgeCorners[e][0] < kEdgeCorners[e][1].
extern const std::array<std::array<std::uint8_t, 2>, 12> kEdgeCorners;

/// The triangles for one corner configuration (bit c set when corner c is inside the object),
/// each as three cell edges, counter-clockwise seen from outside the object.
struct McCase {
    std::uint8_t triangle_count = 0;
    std::array<std::array<std::uint8_t, 3>, 6> triangles{};
};

/// The case for configuration @a config (0..255).
const McCase& mc_case(unsigned config);

}  // namespace vdbmesh::detail
