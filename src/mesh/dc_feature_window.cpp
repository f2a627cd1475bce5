// `--sharp`: a cell's feature point from the faces found in a window wider than the cell.

#include "mesh/dc_feature_window.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "mesh/dc_qef.h"

namespace vdbmesh::detail {

namespace {

/// Two crossings lie on one face when their normals are within 1.8 degrees of each other and
/// the second lies within 0.02 voxel of the first's tangent plane. On a face the phantoms'
/// samples are a linear function of the distance to it, so its crossings and central-difference
/// normals are exact to the floats (1e-6); the rounded zone's normals turn by tens of degrees
/// within a voxel, and a sphere of radius 40 turns 1.8 degrees in 1.3 voxels.
constexpr double kSameFaceCosine = 0.9995;
constexpr double kSameFaceOffset = 0.02;
/// A face is taken from at least this many crossings: the rounded zone's few agreeing
/// neighbours do not make one.
constexpr int kFaceMinCrossings = 6;
/// A face's crossings spread over an area: the smaller spread of their positions across its
/// normal at least this (voxels; the square root of the covariance's middle eigenvalue). Along
/// an axis-aligned edge the rounded zone's crossings repeat along the edge, the same plane each,
/// and would make a face of one line.
constexpr double kFaceMinSpread = 0.5;
/// A face takes part in the cell's feature when its plane passes this close (voxels) to the
/// cell's own estimate, which the rounding moves at most 0.45 voxel off the feature
/// (docs/dmc.md); a face farther away belongs to another edge or corner in the window.
constexpr double kFaceNearEstimate = 1.0;

/// The window's samples, as the meshers read them: a cube of @a dim samples from @a lo.
class WindowSamples {
public:
    WindowSamples(const FeatureWindowSource& source, const openvdb::Coord& lo, int dim) : lo_(lo), dim_(dim) {
        values_.resize(std::size_t(dim) * dim * dim);
        for (int x = 0; x < dim; ++x) {
            for (int y = 0; y < dim; ++y) {
                for (int z = 0; z < dim; ++z) {
                    const openvdb::Coord ijk = lo.offsetBy(x, y, z);
                    values_[index(x, y, z)] = source.classifier->sample_value(ijk, source.accessor->getValue(ijk));
                }
            }
        }
    }
    /// The sample at local (x, y, z).
    double at(int x, int y, int z) const { return values_[index(x, y, z)]; }
    /// Central-difference gradient at local (x, y, z), one sample in from the window's faces.
    Point3d gradient(int x, int y, int z) const {
        return {(at(x + 1, y, z) - at(x - 1, y, z)) * 0.5, (at(x, y + 1, z) - at(x, y - 1, z)) * 0.5,
                (at(x, y, z + 1) - at(x, y, z - 1)) * 0.5};
    }
    const openvdb::Coord& lo() const { return lo_; }

private:
    std::size_t index(int x, int y, int z) const { return (std::size_t(x) * dim_ + y) * dim_ + z; }
    openvdb::Coord lo_;
    int dim_;
    std::vector<double> values_;
};

struct Plane {
    Point3d point;
    Point3d normal;  ///< unit, along the gradient
};

double dot(const Point3d& a, const Point3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// The crossings and normals of the grid edges between local samples @a first and @a last
/// (inclusive, every axis) of @a samples; edges touching a sample beyond the scan box and
/// flat spots give none.
std::vector<Plane> window_planes(const WindowSamples& samples, double iso, const SampleClassifier& classifier, int first, int last) {
    std::vector<Plane> planes;
    for (int x = first; x <= last; ++x) {
        for (int y = first; y <= last; ++y) {
            for (int z = first; z <= last; ++z) {
                const int p[3] = {x, y, z};
                const double f0 = samples.at(x, y, z);
                for (int axis = 0; axis < 3; ++axis) {
                    if (p[axis] == last) continue;
                    const int x1 = x + (axis == 0), y1 = y + (axis == 1), z1 = z + (axis == 2);
                    const double f1 = samples.at(x1, y1, z1);
                    if (classifier.inside(f0) == classifier.inside(f1) || !std::isfinite(f0) || !std::isfinite(f1)) continue;
                    const Point3d p0 = {double(samples.lo().x() + x), double(samples.lo().y() + y), double(samples.lo().z() + z)};
                    Point3d p1 = p0;
                    p1[axis] += 1.0;
                    Plane plane;
                    plane.point = edge_crossing(p0, f0, p1, f1, iso);
                    const double t = plane.point[axis] - p0[axis];
                    const Point3d g0 = samples.gradient(x, y, z), g1 = samples.gradient(x1, y1, z1);
                    for (int a = 0; a < 3; ++a) plane.normal[a] = (1 - t) * g0[a] + t * g1[a];
                    const double length = std::sqrt(dot(plane.normal, plane.normal));
                    if (!(length > 0) || !std::isfinite(length)) continue;
                    for (double& n : plane.normal) n /= length;
                    planes.push_back(plane);
                }
            }
        }
    }
    return planes;
}

/// A face: the crossings agreeing with its first one (kSameFaceCosine, kSameFaceOffset).
struct Face {
    Plane seed;
    Point3d normal_sum{};
    double offset_sum = 0;
    Point3d point_sum{};
    std::array<double, 6> point_products{};  ///< xx, xy, xz, yy, yz, zz
    int count = 0;
    /// Whether the crossings spread over an area (kFaceMinSpread), not along a line.
    bool spread() const {
        Eigen::Matrix3d covariance;
        const auto& p = point_products;
        covariance << p[0], p[1], p[2], p[1], p[3], p[4], p[2], p[4], p[5];
        const Eigen::Vector3d mean(point_sum[0] / count, point_sum[1] / count, point_sum[2] / count);
        covariance = covariance / count - mean * mean.transpose();
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
        eigen.computeDirect(covariance, Eigen::EigenvaluesOnly);
        return eigen.eigenvalues()[1] >= kFaceMinSpread * kFaceMinSpread;  // ascending
    }
    Point3d normal() const {
        const double length = std::sqrt(dot(normal_sum, normal_sum));
        return {normal_sum[0] / length, normal_sum[1] / length, normal_sum[2] / length};
    }
    double offset() const { return offset_sum / count; }
};

/// Unit normals within kSameFaceCosine of each other differ by less than this in each component
/// (sqrt(2 - 2 kSameFaceCosine) = 0.03162, and some room for the rounding of their lengths).
constexpr double kSameFaceComponent = 0.0317;

/// Groups @a planes into faces, each plane into the first face it agrees with, in order.
std::vector<Face> group_faces(const std::vector<Plane>& planes) {
    std::vector<Face> faces;
    // The faces by their seed normal's x, so that a plane is compared only with those whose normal
    // could agree with its own: on a noisy scan nearly every crossing makes a face, and comparing
    // with every face was 84% of a `--sharp` run on the walnut.
    std::vector<std::pair<double, std::uint32_t>> by_x;
    for (const Plane& plane : planes) {
        const double x = plane.normal[0];
        auto first = std::lower_bound(by_x.begin(), by_x.end(), std::make_pair(x - kSameFaceComponent, std::uint32_t(0)));
        std::uint32_t home = std::uint32_t(faces.size());  // the first agreeing face, or a new one
        for (auto it = first; it != by_x.end() && it->first <= x + kSameFaceComponent; ++it) {
            const Face& face = faces[it->second];
            if (it->second < home && dot(face.seed.normal, plane.normal) > kSameFaceCosine &&
                std::abs(dot(face.seed.normal, plane.point) - dot(face.seed.normal, face.seed.point)) < kSameFaceOffset) {
                home = it->second;
            }
        }
        if (home == faces.size()) {
            by_x.insert(std::upper_bound(by_x.begin(), by_x.end(), std::make_pair(x, home)), {x, home});
            faces.push_back({plane});
        }
        Face* const face = &faces[home];
        for (int a = 0; a < 3; ++a) face->normal_sum[a] += plane.normal[a];
        face->offset_sum += dot(plane.normal, plane.point);
        const Point3d& p = plane.point;
        const double products[6] = {p[0] * p[0], p[0] * p[1], p[0] * p[2], p[1] * p[1], p[1] * p[2], p[2] * p[2]};
        for (int i = 0; i < 6; ++i) face->point_products[i] += products[i];
        for (int a = 0; a < 3; ++a) face->point_sum[a] += p[a];
        ++face->count;
    }
    return faces;
}

}  // namespace

std::vector<WindowFace> window_faces(const FeatureWindowSource& source, double iso, const openvdb::Coord& cell_min, int size) {
    // Edges between samples kFeatureWindowGrowth beyond the cell's, one more sample each side
    // for the gradients.
    const int dim = size + 2 * kFeatureWindowGrowth + 3;
    const WindowSamples samples(source, cell_min.offsetBy(-kFeatureWindowGrowth - 1), dim);
    std::vector<WindowFace> kept;
    for (const Face& face : group_faces(window_planes(samples, iso, *source.classifier, 1, dim - 2))) {
        if (face.count >= kFaceMinCrossings && face.spread()) kept.push_back({face.normal(), face.offset()});
    }
    return kept;
}

std::optional<Point3d> feature_point(const std::vector<WindowFace>& faces, const Point3d& estimate) {
    Qef3 feature;
    for (const WindowFace& face : faces) {
        const Point3d& n = face.normal;
        const double distance = dot(n, estimate) - face.offset;
        if (std::abs(distance) > kFaceNearEstimate) continue;
        // The estimate's foot on the face: the points' mean stays near the estimate, so along an
        // edge (a direction no face pins down) the feature point stays where the estimate is.
        feature.add_plane({estimate[0] - distance * n[0], estimate[1] - distance * n[1], estimate[2] - distance * n[2]}, n);
    }
    if (!is_sharp_feature(feature)) return std::nullopt;
    return feature.minimiser();
}

std::optional<Point3d> window_feature_point(const FeatureWindowSource& source, double iso, const openvdb::Coord& cell_min,
                                            int size, const Point3d& estimate) {
    return feature_point(window_faces(source, iso, cell_min, size), estimate);
}

}  // namespace vdbmesh::detail
