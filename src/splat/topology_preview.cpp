// The topology preview (splats.h): a splat per leaf from its active voxels alone, before any
// sample is read. On vdbmesh's grids the active voxels are a band round the surface (the
// converter's), so a leaf's active voxels lie along the surface: their centroid is near it,
// their thinnest direction (the smallest principal axis) across it.

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "splat/splat_build.h"
#include "vdbmesh/grid_region.h"

namespace vdbmesh::splat {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// The splat of one leaf (level 2, in index space; voxel centres at integer coordinates):
/// the centroid of its active voxels, the direction across them, a radius reaching the
/// farthest voxel's far corner. Its normal's sign is unknown (the cone is the whole sphere).
BuildNode leaf_splat(const LeafMask& leaf) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
    std::uint32_t count = 0;
    for (int x = 0; x < 8; ++x)
        for (std::uint64_t word = leaf.on[x]; word != 0; word &= word - 1) {
            const int bit = __builtin_ctzll(word);
            const Eigen::Vector3d p(x, bit / 8, bit % 8);
            sum += p;
            outer += p * p.transpose();
            ++count;
        }
    BuildNode node;
    node.origin = leaf.origin;
    node.weight = count;
    node.cone = float(kPi);
    if (count == 0) return node;
    const Eigen::Vector3d centroid = sum / count;
    const Eigen::Matrix3d covariance = outer / count - centroid * centroid.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
    const Eigen::Vector3d normal = solver.eigenvectors().col(0);  // the smallest eigenvalue's
    double radius = 0;
    for (int x = 0; x < 8; ++x)
        for (std::uint64_t word = leaf.on[x]; word != 0; word &= word - 1) {
            const int bit = __builtin_ctzll(word);
            radius = std::max(radius, (Eigen::Vector3d(x, bit / 8, bit % 8) - centroid).squaredNorm());
        }
    const Eigen::Vector3d world = centroid + Eigen::Vector3d(leaf.origin[0], leaf.origin[1], leaf.origin[2]);
    node.centre = {float(world.x()), float(world.y()), float(world.z())};
    node.normal = {float(normal.x()), float(normal.y()), float(normal.z())};
    node.radius = float(std::sqrt(radius) + std::sqrt(3.0) / 2);  // to the voxel's far corner
    return node;
}

}  // namespace
}  // namespace vdbmesh::splat

namespace vdbmesh {

SplatTree build_topology_preview(const GridRegionSource& source) {
    constexpr std::int32_t far = std::numeric_limits<std::int32_t>::max();
    const std::vector<LeafMask> leaves = source.active_leaves(IndexBox{{-far, -far, -far}, {far, far, far}});
    splat::Levels levels(kSplatRootLevel + 1);
    levels[kSplatLeafLevel].resize(leaves.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 1024), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) levels[kSplatLeafLevel][i] = splat::leaf_splat(leaves[i]);
    });
    SplatOptions options;
    options.coplanar_tolerance = 0;
    return splat::assemble(levels, source.description()->transform(), options, /*unsigned_normals=*/true);
}

}  // namespace vdbmesh
