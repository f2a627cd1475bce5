#pragma once
/// @file mesh_io.h
/// @brief Reading and writing triangle meshes: STL (binary and ASCII), PLY and OBJ (OpenVDB-free).

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
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

/// @brief A mesh file written as a stream, for meshes too large to hold (issue 28): the counts
/// first, then every vertex, then every triangle, in as many calls as wanted, through the same
/// atomic temporary file as write_mesh(), whose bytes it writes for the same mesh. STL writes
/// each triangle's corners, so add_triangle() takes them; per-vertex normals need every
/// triangle before the first vertex, so options.normals is refused.
class MeshStreamWriter {
public:
    /// @throw UsageError for an unknown extension or options.normals, Error when the file
    /// cannot be created.
    MeshStreamWriter(const std::filesystem::path& path, const MeshWriteOptions& options, std::uint64_t vertex_count,
                     std::uint64_t triangle_count);
    ~MeshStreamWriter();
    MeshStreamWriter(const MeshStreamWriter&) = delete;
    MeshStreamWriter& operator=(const MeshStreamWriter&) = delete;

    /// The next vertex; all of them before the first triangle.
    void add_vertex(const std::array<float, 3>& position);
    /// Whether add_triangle() writes the corners it is given into a file named @a path (STL),
    /// or only the vertex numbers (PLY, OBJ). @throw UsageError for an unknown extension.
    static bool writes_corners(const std::filesystem::path& path);
    /// The next triangle (vertex numbers from 0) and the positions of its three vertices.
    void add_triangle(const std::array<std::uint32_t, 3>& triangle, const std::array<std::array<float, 3>, 3>& corners);
    /// Renames the file into place. @throw Error when the counts given at the start were not
    /// met or a write failed; the target is then left as it was.
    void commit();

private:
    struct Stream;
    std::unique_ptr<Stream> stream_;
};

/// A mesh file's records as bytes, the same MeshStreamWriter writes, for ranks that each write
/// their own records at their places in one file (mesher.h's MeshRangeSink).
class MeshRecordFormat {
public:
    /// @throw UsageError for an unknown extension.
    MeshRecordFormat(const std::filesystem::path& path, bool ascii);
    std::string header(std::uint64_t vertex_count, std::uint64_t triangle_count) const;
    std::string footer() const;
    void vertices(const std::vector<std::array<float, 3>>& positions, std::string& out) const;
    /// @a corners is read only for STL (MeshStreamWriter::writes_corners()).
    void triangles(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                   const std::vector<std::array<std::array<float, 3>, 3>>& corners, std::string& out) const;

private:
    int format_;
    bool ascii_;
};

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

/// @brief Receives a mesh file's records in file order, from read_mesh_records(): for meshes
/// too large to hold (issue 28). PLY and OBJ give vertices and triangles (vertex numbers from 0,
/// already checked against the vertices before them); STL gives each facet's corners, unwelded.
class MeshRecordVisitor {
public:
    virtual ~MeshRecordVisitor() = default;
    /// The counts a header announces, before the first record: PLY's vertices and faces (faces
    /// may be polygons), a binary STL's facets (vertices 0: not known before welding).
    virtual void announced(std::uint64_t vertices, std::uint64_t faces) { (void)vertices, (void)faces; }
    virtual void vertex(const std::array<float, 3>& position) = 0;
    /// A triangle; a polygon comes as the triangles of its fan.
    virtual void triangle(const std::array<std::uint32_t, 3>& triangle) = 0;
    virtual void facet(const std::array<std::array<float, 3>, 3>& corners) = 0;
};

/// @brief Reads @a path record by record with the parsing and the checks of read_mesh()
/// (the same FormatError for the same file), holding only a window of the file: it is mapped
/// and the pages read are released as the reading goes on. Compressed (gzip) files, which
/// read_mesh() takes, are refused (FormatError): they cannot be mapped.
void read_mesh_records(const std::filesystem::path& path, MeshRecordVisitor& visitor);

/// The unit normal of each vertex: the area-weighted average of its triangles' normals (0 for
/// a vertex no triangle uses), as PLY and OBJ files get them.
std::vector<std::array<float, 3>> vertex_normals(const Mesh& mesh);

}  // namespace vdbmesh
