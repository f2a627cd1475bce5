#pragma once
// An instanced surface (shared_marching_cubes_instanced) as glTF 2.0: one mesh per distinct
// block, placed by the EXT_mesh_gpu_instancing extension's TRANSLATION attribute. .glb: one
// binary file; .gltf: JSON with the buffer embedded as a base64 data URI. Written through
// CheckedOutput (nothing is left behind on failure).

#include <string>

#include "vdbmesh/shared_tree.h"

namespace vdbmesh::cli {

void write_instanced_gltf(const InstancedMesh& mesh, const std::string& path);

}  // namespace vdbmesh::cli
