#pragma once
/// @file measure.h
/// @brief Measuring the solid a closed mesh bounds: integrals, principal moments and axes,
/// bounding box, genus and connected components (OpenVDB-free; `vdbmesh measure`).

#include <array>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "vdbmesh/analysis.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh {

/// One connected component of a mesh (connected through shared vertices).
struct ComponentMeasure {
    std::size_t triangles = 0;
    double area = 0;
    double volume = 0;  ///< signed: negative for a cavity's surface (normals pointing into it)
};

/// What measure_mesh() finds, in the mesh's (world) units.
struct MeshMeasure {
    /// Validity, genus and the integrals (area, volume, centroid, inertia about the centroid
    /// with unit density), as `vdbmesh check` reports them.
    MeshAnalysis report;
    /// Eigenvalues of report.inertia, ascending.
    std::array<double, 3> principal_moments{};
    /// principal_axes[k] is the unit axis of principal_moments[k]; the three form a
    /// right-handed frame, each with its largest coordinate positive except where the frame's
    /// handedness decides the sign of the third.
    std::array<std::array<double, 3>, 3> principal_axes{};
    std::array<double, 3> box_min{}, box_max{};  ///< of the referenced vertices
    /// Largest |volume| first (ties: larger area first).
    std::vector<ComponentMeasure> components;
};

/// @brief Measures @a mesh: analyze_mesh(), the principal frame of its inertia, its bounding
/// box and each connected component's area and volume (divergence theorem, exact for a closed
/// mesh). @throw Error when a triangle refers to a missing vertex.
MeshMeasure measure_mesh(const Mesh& mesh);

/// @brief measure_mesh() of a mesh given record by record, never held (issue 28): the figures
/// of analyze_mesh_stream() (the same bits as measure_mesh() but self_intersecting_pairs and
/// negative_components, not counted), the principal frame and bounding box from them, and the
/// components' sums: each triangle's area and signed volume (about the mesh's first corner)
/// spooled to an unlinked temporary file, added to its component once the streamed topology
/// has named each vertex's (4 more bytes a vertex). The components' figures agree with
/// measure_mesh()'s to rounding (summed in another order), their order is the same but where
/// rounding breaks a tie. Feed it as read_mesh_records() does (or a bricked mesher's stream:
/// announced(), the vertices, the triangles), then finish().
class MeshMeasureStream final : public MeshRecordVisitor {
public:
    /// @a name (the file) for messages; @a options.memory_bytes the limit.
    /// @throw UsageError, from the first record on, when the limit cannot hold the plan (the
    /// message names the smallest that works).
    MeshMeasureStream(const std::string& name, const StreamCheckOptions& options);
    ~MeshMeasureStream() override;
    /// For an OBJ file: the vertices it holds, before any record (they are not announced).
    void plan_vertices(std::uint64_t vertices);
    void announced(std::uint64_t vertices, std::uint64_t faces) override;
    void vertex(const std::array<float, 3>& position) override;
    void triangle(const std::array<std::uint32_t, 3>& triangle) override;
    void facet(const std::array<std::array<float, 3>, 3>& corners) override;
    MeshMeasure finish();
    /// The least limit of any stream of vertices and triangles (the program, the buffers, two
    /// sorts of 1 MiB); each vertex adds 12.25 bytes to it.
    static std::uint64_t least_bytes();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// @brief MeshMeasureStream over the file @a path (read_mesh_records(); an OBJ file is read
/// twice, first to count its vertices).
MeshMeasure measure_mesh_stream(const std::filesystem::path& path, const StreamCheckOptions& options);

/// @brief The connected components of @a mesh (through shared vertices) as separate meshes,
/// in order of first appearance; each keeps its triangles' order, its vertices are numbered in
/// order of first use. Unreferenced vertices are dropped.
std::vector<Mesh> split_components(const Mesh& mesh);

}  // namespace vdbmesh
