#pragma once
// Private: the parts of a MeshAnalysis that analyze_mesh() and the bounded check
// (analyze_stream.cpp) both fill, so that they report the same figures the same way.

#include <array>
#include <cstddef>

#include "analysis/block_reduce.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh::detail {

/// Angles under this many degrees are "small" (MeshAnalysis::small_angle_share).
constexpr double kSmallAngleDeg = 10.0;

/// The three angles of triangle abc in degrees (via atan2, accurate for tiny angles).
std::array<double, 3> triangle_angles(const std::array<float, 3>& a, const std::array<float, 3>& b, const std::array<float, 3>& c);

/// The counts, Euler characteristic, genus and closedness from @a topology (report.triangles
/// and report.vertices set before).
void add_topology(const Topology& topology, MeshAnalysis& report);

/// The degenerate faces from the count of each FaceClass, and the angle figures from the
/// angles of the regular faces (flagged: under kSmallAngleDeg).
void add_faces(const std::array<std::size_t, 3>& class_counts, const ValueStats& angles, MeshAnalysis& report);

/// Area, volume, centroid, inertia and the outward verdict.
void add_integrals(const MeshIntegrals& integrals, MeshAnalysis& report);

}  // namespace vdbmesh::detail
