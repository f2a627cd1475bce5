// The topology preview (splats.h): a splat per leaf from its active voxels alone, before any
// sample is read. On vdbmesh's grids the active voxels are a band round the surface (the
// converter's), so a leaf's active voxels lie along the surface: their centroid is near it,
// their thinnest direction (the smallest principal axis) across it.

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <limits>

#include "splat/splat_build.h"
#include "vdbmesh/grid_region.h"

namespace vdbmesh::splat {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Sums over the set bits of a byte (bit z: z = 0..7): how many, of z and of z^2.
struct ByteSums {
    std::array<std::uint8_t, 256> count{}, z{}, zz{};
    ByteSums() {
        for (int byte = 0; byte < 256; ++byte)
            for (int z = 0; z < 8; ++z)
                if (byte >> z & 1) {
                    count[byte] += 1;
                    this->z[byte] += std::uint8_t(z);
                    zz[byte] += std::uint8_t(z * z);
                }
    }
};
const ByteSums kByteSums;

/// The splat of one leaf (level 2, in index space; voxel centres at integer coordinates):
/// the centroid of its active voxels, the direction across them, a radius reaching the
/// farthest voxel's far corner. Its normal's sign is unknown (the cone is the whole sphere).
/// The sums of the coordinates and their products are counted in integers a row of 8 voxels
/// at a time (exact: the same doubles as summing voxel by voxel), and the farthest voxel is
/// sought among each row's two ends (the farthest of a row along z is one of them).
BuildNode leaf_splat(const LeafMask& leaf) {
    std::int64_t n = 0, sx = 0, sy = 0, sz = 0, sxx = 0, syy = 0, szz = 0, sxy = 0, sxz = 0, syz = 0;
    for (int x = 0; x < 8; ++x)
        for (int y = 0; y < 8; ++y) {
            const unsigned byte = unsigned(leaf.on[x] >> (8 * y)) & 0xffu;
            if (byte == 0) continue;
            const std::int64_t c = kByteSums.count[byte], z = kByteSums.z[byte], zz = kByteSums.zz[byte];
            n += c;
            sx += x * c;
            sy += y * c;
            sz += z;
            sxx += x * x * c;
            syy += y * y * c;
            szz += zz;
            sxy += x * y * c;
            sxz += x * z;
            syz += y * z;
        }
    BuildNode node;
    node.origin = leaf.origin;
    node.weight = std::uint32_t(n);
    node.cone = float(kPi);
    if (n == 0) return node;
    const Eigen::Vector3d sum(static_cast<double>(sx), static_cast<double>(sy), static_cast<double>(sz));
    Eigen::Matrix3d outer;
    outer << double(sxx), double(sxy), double(sxz), double(sxy), double(syy), double(syz), double(sxz), double(syz), double(szz);
    const auto count = std::uint32_t(n);
    const Eigen::Vector3d centroid = sum / count;
    const Eigen::Matrix3d covariance = outer / count - centroid * centroid.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
    const Eigen::Vector3d normal = solver.eigenvectors().col(0);  // the smallest eigenvalue's
    double radius = 0;
    for (int x = 0; x < 8; ++x)
        for (int y = 0; y < 8; ++y) {
            const unsigned byte = unsigned(leaf.on[x] >> (8 * y)) & 0xffu;
            if (byte == 0) continue;
            for (const int z : {__builtin_ctz(byte), 31 - __builtin_clz(byte)})
                radius = std::max(radius, (Eigen::Vector3d(x, y, z) - centroid).squaredNorm());
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
