#pragma once
// Private: `--sharp`'s feature point of a cell from Hermite data of a window wider than the cell
// (docs/dmc.md, "Sharp features"). Near an edge or a corner the trilinear isosurface is rounded
// over about 1.5 voxels: the crossings there and their normals (central differences) miss the
// feature, and in a cell of 2-8 voxels they are most of its planes, so the cell's own QEF puts
// a corner 0.35-0.45 voxel inside. Farther out, on each face, the crossings and normals are exact
// and agree with one another: the window's planes are grouped into faces (planes that agree in
// normal and offset), and the feature is where the faces passing by the cell meet.

#include <openvdb/openvdb.h>

#include <optional>
#include <vector>

#include "mesh/edge_crossing.h"
#include "mesh/sample_classifier.h"

namespace vdbmesh::detail {

/// Where a block's samples were read from (load_ifc_samples()): the thread's accessor and the
/// classifier, which the window reads the same way (samples beyond the scan box outside).
struct FeatureWindowSource {
    openvdb::FloatGrid::ConstAccessor* accessor = nullptr;
    const SampleClassifier* classifier = nullptr;
};

/// How far (voxels) the window reaches beyond the cell on every side: the rounding reaches about
/// 1.5 voxels from an edge, so a face needs some exact crossings beyond it within the window.
inline constexpr int kFeatureWindowGrowth = 3;

/// A face found in a window: a plane (unit normal, offset: normal . x = offset on it).
struct WindowFace {
    Point3d normal;
    double offset;
};

/// The faces found in the window round the cell at @a cell_min of @a size (index space): its
/// crossings and normals grouped into planes that agree, each of enough crossings spread over an
/// area; none on a rounded or noisy surface.
std::vector<WindowFace> window_faces(const FeatureWindowSource& source, double iso, const openvdb::Coord& cell_min, int size);

/// Where those of @a faces that pass within a voxel of @a estimate meet (nearest @a estimate
/// along an edge), when they pin down two or three directions; none otherwise.
std::optional<Point3d> feature_point(const std::vector<WindowFace>& faces, const Point3d& estimate);

/// The feature point of the cell at @a cell_min of @a size (index space) whose own QEF holds an
/// edge or a corner and puts it at @a estimate: feature_point() of its window_faces().
std::optional<Point3d> window_feature_point(const FeatureWindowSource& source, double iso, const openvdb::Coord& cell_min,
                                            int size, const Point3d& estimate);

}  // namespace vdbmesh::detail
