#pragma once
/// @file mesh.h
/// @brief The indexed triangle mesh every mesher returns and every writer takes (OpenVDB-free).

#include <array>
#include <cstdint>
#include <vector>

namespace vdbmesh {

/// An indexed triangle mesh in world coordinates. Triangles are counter-clockwise seen
/// from outside (normals point out of the object).
struct Mesh {
    std::vector<std::array<float, 3>> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

}  // namespace vdbmesh
