#pragma once
// Private: the gradient Dual Marching Cubes gives a sample's tangent hyperplane (dmc_qef.h),
// fitted so that sharp features survive. Central differences at a sample next to a crease of
// the field (the medial surface of an edge or corner, where the signed distance has a kink)
// average the planes on both sides, and the tangent no longer passes through the feature.
// Here the plane is fitted by least squares to the samples of the 3x3x3 neighbourhood, or,
// when those are not planar, to the half of it (cut by a plane through the sample) or the
// octant that is most planar: the part on the sample's own side of the crease (ENO-like
// stencil choice, Harten et al. 1987, in 3D). Samples with no planar part (a cone apex, strong
// curvature, scan noise) keep the plane of the whole neighbourhood.

#include <openvdb/openvdb.h>

#include <array>
#include <optional>

#include "mesh/edge_crossing.h"

namespace vdbmesh::detail {

/// The 3x3x3 values around a sample, index (i + 1) * 9 + (j + 1) * 3 + (k + 1) for the offset
/// (i, j, k) in {-1, 0, 1}^3, in units where the gradient is about 1 (voxels).
using Neighbourhood = std::array<double, 27>;

/// The gradient of the least-squares plane through the sample over its whole neighbourhood
/// (a smoothed central difference); nothing when a value is not finite. Noise on a scan
/// averages out in it, which is what the merge decision of the octree needs.
std::optional<Point3d> sample_gradient(const Neighbourhood& f);

/// The gradient of the sample's tangent plane (through its value at offset 0): the best
/// planar part's, or sample_gradient() when no part is planar (noise, strong curvature);
/// nothing when a value is not finite.
std::optional<Point3d> sample_tangent(const Neighbourhood& f);

/// Distance (voxels) from index-space point @a p to the nearest tangent plane (at @a iso) of
/// the 8 samples around it, read through @a accessor, among those fitting their samples to
/// within 0.005 voxel RMS; infinity when none does. Unlike
/// the trilinear field, which rounds edges and corners by up to 0.58 voxel, the planes keep
/// them: a point on a sharp feature reads as on the surface. The distance can read short
/// outside a convex feature (by up to sqrt(3) at a cube's corner, where the surface is the
/// corner point, not the planes' extensions), so it complements a smooth estimate.
double tangent_plane_distance(const openvdb::FloatGrid::ConstAccessor& accessor, double iso, const openvdb::Vec3d& p);

}  // namespace vdbmesh::detail
