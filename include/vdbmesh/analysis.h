#pragma once
/// @file analysis.h
/// @brief Validating and measuring triangle meshes: topology, degeneracies, exact
/// self-intersections (geometry.h), integrals (area, volume, centroid, inertia) and
/// distances (OpenVDB-free).

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <utility>
#include <vector>

#include "vdbmesh/geometry.h"  // find_self_intersections()
#include "vdbmesh/mesh.h"

namespace vdbmesh {

/// What analyze_mesh() finds. Nothing is repaired; every count is of the mesh as given.
struct MeshAnalysis {
    // Sizes.
    std::size_t triangles = 0;
    std::size_t vertices = 0;               ///< mesh.vertices.size()
    std::size_t unreferenced_vertices = 0;  ///< vertices used by no triangle
    std::size_t edges = 0;                  ///< distinct undirected edges (self-loops excluded)

    // Topology (edges of repeated-vertex faces are counted like any other, self-loops skipped).
    std::size_t boundary_edges = 0;       ///< edges used by one triangle
    std::size_t boundary_loops = 0;       ///< connected components of the boundary edges
    std::size_t nonmanifold_edges = 0;    ///< edges used by more than two triangles
    std::size_t nonmanifold_vertices = 0; ///< vertices whose triangles form more than one fan
    std::size_t misoriented_edges = 0;    ///< edges used twice in the same direction
    std::size_t components = 0;           ///< connected through shared vertices
    long long euler_characteristic = 0;   ///< V - E + F over referenced vertices
    /// Sum of the components' genera, from V - E + F = 2C - 2g - B (B boundary loops);
    /// -1 when the mesh is not manifold (the formula does not apply).
    long long genus = -1;
    bool closed = false;    ///< no boundary edges (and at least one triangle)

    // Degeneracies.
    std::size_t repeated_vertex_faces = 0;  ///< a vertex index used twice in one triangle
    std::size_t zero_area_faces = 0;        ///< distinct indices but exactly collinear corners
    std::size_t degenerate_faces = 0;       ///< the sum of both

    /// Pairs of non-degenerate triangles that share a point they are not required to share
    /// (see find_self_intersections()).
    std::size_t self_intersecting_pairs = 0;

    // Integrals (unit density; meaningful for closed meshes).
    double area = 0;
    double volume = 0;                       ///< signed: positive when the normals point out
    std::array<double, 3> centroid{};        ///< of the solid (of the surface when volume is 0)
    std::array<std::array<double, 3>, 3> inertia{};  ///< about the centroid, unit density
    /// Total signed volume > 0. Components with negative volume are counted separately:
    /// a cavity inside another component is legitimately negative.
    bool outward = false;
    std::size_t negative_components = 0;

    // Quality of non-degenerate triangles.
    double min_angle_deg = 0;
    double small_angle_share = 0;  ///< share of angles under 10 degrees

    /// Closed, manifold (edges and vertices), consistently oriented, outward, no
    /// self-intersections, no degenerate faces, at least one triangle.
    bool is_clean() const;
};

/// Measures and validates @a mesh (parallel with TBB; deterministic).
MeshAnalysis analyze_mesh(const Mesh& mesh);

/// What analyze_mesh_stream() may use.
struct StreamCheckOptions {
    std::uint64_t memory_bytes = 0;  ///< the limit on the process's peak (`check --memory`)
    /// Records per sorted run; 0: as many as the limit allows. Tests make it small to force
    /// several runs through the temporary files on small meshes.
    std::size_t run_records = 0;
    /// Called now and then with the share of the work done (0 to 1), when set.
    std::function<void(double)> progress;
};

/// What analyze_mesh_stream() finds.
struct StreamCheck {
    /// As analyze_mesh() reports it, but for self_intersecting_pairs and negative_components,
    /// which are not counted (0): the first needs every triangle at hand, the second each
    /// triangle's component before the triangles are summed.
    MeshAnalysis analysis;
    std::size_t sorted_runs = 0;  ///< runs written to temporary files (0: every sort fitted in memory)
};

/// @brief analyze_mesh() of the mesh in @a path read as a stream, within about
/// options.memory_bytes whatever the file's size (issue 28). The edges (and each vertex's
/// corners) are sorted in runs that fit the limit, written to unlinked temporary files in
/// $TMPDIR, and merged; STL corners are welded by exact position the same way. Held whole:
/// 12 bytes a vertex while a PLY or OBJ file is read (the positions, for each triangle's
/// area, volume and degeneracy), 8.25 bytes a vertex while the topology is counted (two
/// union-finds); an OBJ file is read twice (first to count its vertices). The figures are those
/// of analyze_mesh() on read_mesh(), bit for bit (integrals summed in the same blocks).
/// @throw UsageError naming the smallest limit that works when the limit is too small,
/// FormatError as read_mesh() for a bad file, Error when the temporary files cannot be written.
StreamCheck analyze_mesh_stream(const std::filesystem::path& path, const StreamCheckOptions& options);

/// Area, signed volume, centroid and inertia about the centroid (unit density) of the solid
/// bounded by @a mesh, by the divergence theorem on its triangles (exact for a closed mesh).
struct MeshIntegrals {
    double area = 0;
    double volume = 0;
    std::array<double, 3> centroid{};
    std::array<std::array<double, 3>, 3> inertia{};
};
MeshIntegrals mesh_integrals(const Mesh& mesh);

/// Distances between two surfaces, from points sampled uniformly by area on each.
struct DistanceReport {
    double hausdorff = 0;    ///< max of both one-sided maxima
    double max_a_to_b = 0;
    double max_b_to_a = 0;
    double mean_a_to_b = 0;
    double mean_b_to_a = 0;
    double mean = 0;         ///< (mean_a_to_b + mean_b_to_a) / 2
    double rms = 0;          ///< over all samples of both directions
};

/// @brief Two-sided distance between meshes: @a samples_per_mesh points drawn uniformly by
/// area on each (fixed seed: deterministic), each measured exactly to the closest point of
/// the other mesh through a bounding-volume hierarchy.
/// @throw Error when a mesh has no triangle of positive area.
DistanceReport mesh_distance(const Mesh& a, const Mesh& b, std::size_t samples_per_mesh);

/// @a count points drawn uniformly by area on @a mesh with the sampler of mesh_distance()
/// (fixed seed: deterministic), e.g. to measure a reference surface against many meshes.
/// @throw Error when the mesh has no triangle of positive area.
std::vector<std::array<double, 3>> sample_surface(const Mesh& mesh, std::size_t count);

/// @brief Distance between @a mesh and an analytic surface {signed_distance = 0}:
/// mesh -> surface from @a samples points on the mesh, |signed_distance(p)| each (the function
/// is called concurrently and must be thread-safe); surface -> mesh from the caller's
/// @a surface_points measured exactly to the mesh. With no surface points the b-to-a fields are 0.
DistanceReport mesh_distance(const Mesh& mesh, const std::function<double(double, double, double)>& signed_distance,
                             std::size_t samples, const std::vector<std::array<double, 3>>& surface_points = {});

}  // namespace vdbmesh
