#pragma once
// The body of GET /api/mesh: the buffers WebGL draws from, back to back and little-endian.

#include <string>

#include "vdbmesh/mesh.h"

namespace vdbmesh::view {

/// Positions (float32 x 3 per vertex), then per-vertex normals (float32 x 3, area-weighted,
/// as the PLY and OBJ writers give them), then indices (uint32 x 3 per triangle):
/// 24 V + 12 T bytes.
std::string mesh_buffers(const Mesh& mesh);

}  // namespace vdbmesh::view
