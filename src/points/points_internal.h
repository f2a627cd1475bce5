#pragma once
// Helpers shared by the files of the points stage (private).

#include <vector>

#include "vdbmesh/points.h"

namespace vdbmesh::points_detail {

struct PcaResult {
    Vec3d normal;
    double variation = 0;  ///< smallest eigenvalue over their sum (surface variation)
};
/// PCA of the points of @a index: the normal (unoriented) and the surface variation.
PcaResult pca_normal(const std::vector<Vec3d>& points, const std::vector<std::size_t>& index);

/// Keeps the points (and their normals and scans) where keep[i] is non-zero.
void keep_points(PointCloud& cloud, const std::vector<char>& keep);

}  // namespace vdbmesh::points_detail
