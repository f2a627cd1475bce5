#pragma once
/// @file process.h
/// @brief Processing a mesh after meshing, keeping it closed, manifold and free of
/// self-intersections: Taubin smoothing and quadric decimation (OpenVDB-free; `vdbmesh mesh
/// --taubin, --decimate, --max-error`). Grid filters before meshing: grid_filter.h.

#include <cstddef>
#include <limits>

#include "vdbmesh/mesh.h"

namespace vdbmesh {

/// Options of taubin_smooth(): G. Taubin, "A signal processing approach to fair surface
/// design", SIGGRAPH 1995 (uniform weights; lambda > 0 shrinks, mu < -lambda inflates back).
struct TaubinOptions {
    int iterations = 1;   ///< lambda/mu pairs
    double lambda = 0.5;
    double mu = -0.53;
};

/// What taubin_smooth() did.
struct TaubinReport {
    std::size_t held_back = 0;  ///< vertex moves undone (summed over the steps) to avoid a self-intersection or a degenerate face
};

/// @brief Taubin's lambda/mu smoothing of @a mesh. After each step the moved mesh is checked
/// (exact self-intersections, degenerate faces); the vertices of every offending triangle go
/// back to where they were, until the check passes, so a mesh that was free of
/// self-intersections stays so. Connectivity is unchanged.
/// @throw UsageError for iterations < 0 or non-finite factors; Error for a bad index.
Mesh taubin_smooth(const Mesh& mesh, const TaubinOptions& options, TaubinReport* report = nullptr);

/// Options of decimate_mesh(): collapse edges while both bounds allow.
struct DecimateOptions {
    double keep_fraction = 0;  ///< stop at this share of the triangles, in [0, 1] (0: as far as max_error allows)
    /// Stop at this many triangles or fewer (a collapse removes two), in place of keep_fraction
    /// when not 0.
    std::size_t target_triangles = 0;
    /// Stop before a collapse whose new vertex lies farther than this (world units) from the
    /// plane of an input triangle merged into it (the square root of its unweighted quadric error).
    double max_error = std::numeric_limits<double>::infinity();
};

/// What decimate_mesh() did.
struct DecimateReport {
    std::size_t collapses = 0;
    std::size_t rejected_topology = 0;      ///< collapses refused by the link condition
    std::size_t rejected_geometry = 0;      ///< refused for a flipped, degenerate or needle triangle
    std::size_t rejected_intersection = 0;  ///< refused because a new triangle would cross another
    double max_error = 0;                   ///< largest quadric error bound of a collapse made
};

/// @brief Quadric edge-collapse simplification (M. Garland and P. Heckbert, "Surface
/// simplification using quadric error metrics", SIGGRAPH 1997) of a closed, manifold mesh,
/// keeping it closed, manifold, oriented and free of self-intersections: every collapse is
/// checked around the collapsed edge (link condition, no flipped or degenerate triangle, no
/// intersection of the new triangles with the triangles near them) and skipped when a check
/// fails. Most collapses are cleared of intersections by a proof (every triangle near them faces
/// a common direction, in one component), the others by exact tests; the proof holds for a mesh
/// free of self-intersections, so one that crosses itself is not made free of them. Vertices
/// stay floats, and the checks are made on the floats written.
/// @throw UsageError for keep_fraction outside [0, 1] or a negative max_error; Error when the
/// mesh is not closed and manifold.
Mesh decimate_mesh(const Mesh& mesh, const DecimateOptions& options, DecimateReport* report = nullptr);

}  // namespace vdbmesh
