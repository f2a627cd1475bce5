// refine_to_isosurface(): each triangle split into four at its edge midpoints, then every vertex
// moved by Newton steps along the gradient onto the isosurface of the triquadratic interpolant of
// the samples. The interpolant is exact for fields that are quadratic polynomials (such as the
// level set of an ellipsoid), where the linear interpolation along grid edges of Marching Cubes
// puts every vertex slightly inside a convex surface; the split quarters the chord error of the
// flat triangles between the vertices.
//
// Along each axis the interpolant is the parabola through three samples: those around the sample
// below x (as openvdb::tools::QuadraticSampler takes them), shifted inwards at the faces of the
// scanned box so that it reads only scanned samples. A parabola through any three samples is exact
// for a quadratic field, so the vertices next to the faces are refined as well (on scikit-image's
// anisotropic ellipsoid the lower poles lie on the first samples).
#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_map>

#include "vdbmesh/grid.h"
#include "vdbmesh/grid_filter.h"

namespace vdbmesh {
namespace {

constexpr int kNewtonSteps = 8;
constexpr double kMaxShift = 0.5;    ///< voxels: a vertex moves at most this far
constexpr double kConverged = 1e-9;  ///< voxels: a step this short ends the iteration

/// The triquadratic interpolant of the samples, with its exact gradient.
class QuadraticField {
public:
    QuadraticField(const openvdb::FloatGrid& grid, const std::optional<openvdb::CoordBBox>& box)
        : accessor_(grid.getConstAccessor()), box_(box) {}

    /// The interpolant at @a x (index space) and its gradient.
    double value(const openvdb::Vec3d& x, openvdb::Vec3d* gradient = nullptr) const {
        std::array<int, 3> first{};
        std::array<std::array<double, 3>, 3> weight{}, slope{};
        for (int k = 0; k < 3; ++k) {
            first[k] = int(std::floor(x[k])) - 1;
            if (box_ && box_->max()[k] - box_->min()[k] >= 2) first[k] = std::clamp(first[k], box_->min()[k], box_->max()[k] - 2);
            // Lagrange weights of the nodes 0, 1, 2 at t, and their derivatives.
            const double t = x[k] - first[k];
            weight[k] = {(t - 1) * (t - 2) / 2, -t * (t - 2), t * (t - 1) / 2};
            slope[k] = {t - 1.5, 2 - 2 * t, t - 0.5};
        }
        double sum = 0;
        openvdb::Vec3d g(0.0);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                for (int l = 0; l < 3; ++l) {
                    const double v = accessor_.getValue(openvdb::Coord(first[0] + i, first[1] + j, first[2] + l));
                    sum += v * weight[0][i] * weight[1][j] * weight[2][l];
                    g[0] += v * slope[0][i] * weight[1][j] * weight[2][l];
                    g[1] += v * weight[0][i] * slope[1][j] * weight[2][l];
                    g[2] += v * weight[0][i] * weight[1][j] * slope[2][l];
                }
            }
        }
        if (gradient) *gradient = g;
        return sum;
    }

    /// Whether the interpolant at @a x reads scanned samples near x (beyond the scanned box the
    /// grid holds the background, and the parabolas would extrapolate).
    bool readable(const openvdb::Vec3d& x) const {
        if (!box_) return true;
        for (int k = 0; k < 3; ++k) {
            if (!(x[k] >= box_->min()[k] && x[k] <= box_->max()[k]) || box_->max()[k] - box_->min()[k] < 2) return false;
        }
        return true;
    }

private:
    openvdb::FloatGrid::ConstAccessor accessor_;
    std::optional<openvdb::CoordBBox> box_;
};

/// The point of the isosurface reached from @a start, or @a start when Newton's method strays
/// (farther than kMaxShift, or out of the readable box).
openvdb::Vec3d project(const QuadraticField& field, const openvdb::Vec3d& start, double iso) {
    openvdb::Vec3d x = start;
    for (int i = 0; i < kNewtonSteps; ++i) {
        openvdb::Vec3d g;
        const double value = field.value(x, &g);
        const double length_squared = g.lengthSqr();
        if (!(length_squared > 0)) return start;
        const openvdb::Vec3d step = g * ((value - iso) / length_squared);
        x -= step;
        if ((x - start).length() > kMaxShift || !field.readable(x)) return start;
        if (step.length() < kConverged) break;
    }
    return std::abs(field.value(x) - iso) <= std::abs(field.value(start) - iso) ? x : start;
}

/// Each triangle split into four at its edge midpoints (shared by the two triangles of an edge).
Mesh split_in_four(const Mesh& mesh) {
    Mesh result;
    result.vertices = mesh.vertices;
    std::unordered_map<std::uint64_t, std::uint32_t> midpoint;
    const auto middle = [&](std::uint32_t a, std::uint32_t b) {
        const std::uint64_t key = std::uint64_t(std::min(a, b)) << 32 | std::max(a, b);
        const auto [found, added] = midpoint.emplace(key, std::uint32_t(result.vertices.size()));
        if (added) {
            const auto& p = mesh.vertices[a];
            const auto& q = mesh.vertices[b];
            result.vertices.push_back({(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2});
        }
        return found->second;
    };
    for (const auto& t : mesh.triangles) {
        const std::uint32_t ab = middle(t[0], t[1]), bc = middle(t[1], t[2]), ca = middle(t[2], t[0]);
        result.triangles.push_back({t[0], ab, ca});
        result.triangles.push_back({ab, t[1], bc});
        result.triangles.push_back({ca, bc, t[2]});
        result.triangles.push_back({ab, bc, ca});
    }
    return result;
}

}  // namespace

void refine_to_isosurface(Mesh& mesh, const openvdb::FloatGrid& grid, double iso) {
    mesh = split_in_four(mesh);
    const std::optional<openvdb::CoordBBox> box = stored_scan_box(grid);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.vertices.size(), 1024), [&](const auto& range) {
        const QuadraticField field(grid, box);
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            auto& p = mesh.vertices[v];
            const openvdb::Vec3d start = grid.worldToIndex(openvdb::Vec3d(p[0], p[1], p[2]));
            if (!field.readable(start)) continue;
            const openvdb::Vec3d world = grid.indexToWorld(project(field, start, iso));
            p = {float(world[0]), float(world[1]), float(world[2])};
        }
    });
}

}  // namespace vdbmesh
