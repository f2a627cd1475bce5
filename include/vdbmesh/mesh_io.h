#pragma once
/// @file mesh_io.h
/// @brief Reading and writing triangle meshes: STL (binary and ASCII), PLY and OBJ (OpenVDB-free).

#include <array>
#include <filesystem>
#include <vector>

#include "vdbmesh/mesh.h"

namespace vdbmesh {

/// How write_mesh() encodes a file; the format itself comes from the extension.
struct MeshWriteOptions {
    bool ascii = false;    ///< ASCII STL / ASCII PLY instead of binary (OBJ is always text)
    bool normals = false;  ///< per-vertex normals (area-weighted averages) in PLY and OBJ
};

/// @brief Writes @a mesh to @a path, choosing the format by extension (.stl, .ply, .obj,
/// case-insensitive). STL facet normals come from the triangles; PLY is binary little-endian
/// unless options.ascii. ASCII numbers are written in their shortest round-trip form, so
/// reading the file back gives bit-identical coordinates. The file is written atomically.
/// @throw UsageError for an unknown extension, Error when the file cannot be written.
void write_mesh(const Mesh& mesh, const std::filesystem::path& path, const MeshWriteOptions& options = {});

/// @brief Reads a mesh, choosing the format by extension (.stl, .ply, .obj).
/// - STL: binary or ASCII, told apart by the file size (a binary file is exactly 84 + 50 n
///   bytes), not by a "solid" prefix. Corners are welded ONLY when their coordinates are
///   bit-identical, in order of first appearance; nothing is repaired.
/// - PLY: ascii, binary_little_endian and binary_big_endian; vertex x, y, z of any scalar type;
///   faces as a list (vertex_indices or vertex_index) with any integer count and index types;
///   polygons are triangulated as fans; other elements and properties are skipped.
/// - OBJ: `v` and `f` (forms a, a/b, a/b/c, a//c, negative indices relative to the end);
///   other statements are ignored; polygons are triangulated as fans.
/// @throw FormatError (file, field, expected, actual) for a malformed or truncated file, and
/// for a file with no triangle (an empty file, random bytes or text read as OBJ, a PLY of points
/// only): no valid record is no mesh. UsageError for an unknown extension.
Mesh read_mesh(const std::filesystem::path& path);

/// The unit normal of each vertex: the area-weighted average of its triangles' normals (0 for
/// a vertex no triangle uses), as PLY and OBJ files get them.
std::vector<std::array<float, 3>> vertex_normals(const Mesh& mesh);

}  // namespace vdbmesh
