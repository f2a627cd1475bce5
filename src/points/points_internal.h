#pragma once
// Helpers shared by the files of the points stage (private).

#include <cstdint>
#include <vector>

#include "vdbmesh/points.h"

namespace vdbmesh::points_detail {

struct PcaResult {
    Vec3d normal;
    double variation = 0;  ///< smallest eigenvalue over their sum (surface variation)
};
/// PCA of the points of @a index: the normal (unoriented) and the surface variation.
PcaResult pca_normal(const std::vector<Vec3d>& points, const std::vector<std::size_t>& index);

class KdTree;

/// What the adaptive decimation needs of each point.
struct PointFeatures {
    std::vector<double> variation;  ///< PCA surface variation over the k nearest neighbours
    std::vector<double> density;    ///< points per area around it (k over the squared k-th distance)
};
PointFeatures point_features(const std::vector<Vec3d>& points, const KdTree& tree, int neighbours);

/// The adaptive decimation of chapter 2.4 on given leaves (lists of the numbers of @a points
/// points; leaves may share points): removes options.fraction of the points held by some leaf,
/// each from every leaf holding it, never leaving a leaf with fewer than options.min_per_leaf
/// (so fewer may go). Leaves keep their order.
void decimate_leaves(std::vector<std::vector<std::uint32_t>>& leaves, std::size_t points, const PointFeatures& features,
                     const DecimateOptions& options);

/// The points (and normals) that fall in one cell of a grid of side @a cell, averaged; cells
/// whose normals cancel out are dropped. Deterministic: cells in key order, points in input order.
PointCloud average_per_cell(const PointCloud& cloud, double cell);

/// Keeps the points (and their normals and scans) where keep[i] is non-zero.
void keep_points(PointCloud& cloud, const std::vector<char>& keep);

}  // namespace vdbmesh::points_detail
