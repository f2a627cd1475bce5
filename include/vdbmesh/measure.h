#pragma once
/// @file measure.h
/// @brief Measuring the solid a closed mesh bounds: integrals, principal moments and axes,
/// bounding box, genus and connected components (OpenVDB-free; `vdbmesh measure`).

#include <array>
#include <cstddef>
#include <vector>

#include "vdbmesh/analysis.h"
#include "vdbmesh/mesh.h"

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

/// @brief The connected components of @a mesh (through shared vertices) as separate meshes,
/// in order of first appearance; each keeps its triangles' order, its vertices are numbered in
/// order of first use. Unreferenced vertices are dropped.
std::vector<Mesh> split_components(const Mesh& mesh);

}  // namespace vdbmesh
