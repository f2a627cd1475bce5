// refine_to_isosurface(): each triangle split into four at its edge midpoints, then every vertex
// moved by Newton steps along the gradient onto the isosurface of the triquadratic interpolant of
// the samples (openvdb::tools::QuadraticSampler). The interpolant is exact for fields that are
// quadratic polynomials (such as the level set of an ellipsoid), where the linear interpolation
// along grid edges of Marching Cubes puts every vertex slightly inside a convex surface; the
// split quarters the chord error of the flat triangles between the vertices.
#include <openvdb/tools/Interpolation.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "vdbmesh/grid.h"
#include "vdbmesh/grid_filter.h"

namespace vdbmesh {
namespace {

constexpr int kNewtonSteps = 8;
constexpr double kMaxShift = 0.5;         ///< voxels: a vertex moves at most this far
constexpr double kGradientStep = 1e-3;    ///< voxels: central differences of the interpolant
constexpr double kConverged = 1e-9;       ///< voxels: a step this short ends the iteration

class QuadraticField {
public:
    explicit QuadraticField(const openvdb::FloatGrid& grid) : accessor_(grid.getConstAccessor()) {}
    double value(const openvdb::Vec3d& x) const { return openvdb::tools::QuadraticSampler::sample(accessor_.tree(), x); }
    openvdb::Vec3d gradient(const openvdb::Vec3d& x) const {
        openvdb::Vec3d g;
        for (int k = 0; k < 3; ++k) {
            openvdb::Vec3d step(0.0);
            step[k] = kGradientStep;
            g[k] = (value(x + step) - value(x - step)) / (2 * kGradientStep);
        }
        return g;
    }

private:
    openvdb::FloatGrid::ConstAccessor accessor_;
};

/// The point of the isosurface reached from @a start, or @a start when Newton's method strays
/// (farther than kMaxShift, or where @a readable says the interpolant reads beyond the samples).
template <class Readable>
openvdb::Vec3d project(const QuadraticField& field, const openvdb::Vec3d& start, double iso, const Readable& readable) {
    openvdb::Vec3d x = start;
    for (int i = 0; i < kNewtonSteps; ++i) {
        const openvdb::Vec3d g = field.gradient(x);
        const double length_squared = g.lengthSqr();
        if (!(length_squared > 0)) return start;
        const openvdb::Vec3d step = g * ((field.value(x) - iso) / length_squared);
        x -= step;
        if ((x - start).length() > kMaxShift || !readable(x)) return start;
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
    // The interpolant at x reads the samples around the voxel nearest x, one voxel each way: all
    // of them must be scanned samples (beyond the scanned box the grid holds the background).
    const auto readable = [&](const openvdb::Vec3d& x) {
        if (!box) return true;
        for (int k = 0; k < 3; ++k) {
            if (x[k] < box->min()[k] + 0.5 + 2 * kGradientStep || x[k] > box->max()[k] - 0.5 - 2 * kGradientStep) return false;
        }
        return true;
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.vertices.size(), 1024), [&](const auto& range) {
        const QuadraticField field(grid);
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            auto& p = mesh.vertices[v];
            const openvdb::Vec3d start = grid.worldToIndex(openvdb::Vec3d(p[0], p[1], p[2]));
            if (!readable(start)) continue;
            const openvdb::Vec3d world = grid.indexToWorld(project(field, start, iso, readable));
            p = {float(world[0]), float(world[1]), float(world[2])};
        }
    });
}

}  // namespace vdbmesh
