#pragma once
/// @file trilinear_field.h
/// @brief The grid stage's trilinear interpolant of a float grid in index space, with its
/// exact gradient (the derivative of the interpolating polynomial inside the cell holding the
/// point), and the search for the nearest point of its isosurface (isosurface_search.cpp):
/// the surface sample-based meshers approximate. The DMC self-check and compare.h measure
/// against it. Includes OpenVDB; in vdbmesh::detail: shared between the stages, not a stable API.

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "vdbmesh/grid.h"

namespace vdbmesh::detail {

/// How far from a point its nearest isosurface point is searched for (voxels); compare.h
/// repeats it as kIsosurfaceSearchVoxels.
inline constexpr double kTrilinearSearchVoxels = 4.0;

/// Value and gradient of the interpolant at a point (index space).
struct FieldSample {
    double value = 0;
    openvdb::Vec3d gradient{0, 0, 0};
};

/// Not thread-safe (it caches tree nodes in an accessor): one per thread.
/// With a scan box, points are first clamped into it (the samples are extended constantly
/// beyond the last one, and the gradient has no component across the box face there): the
/// meshers close the surface at the box's faces half a voxel out (edge_crossing.h), and the
/// true solid is then {field > iso} cut by that box (see closest_boundary_point()).
class TrilinearField {
public:
    explicit TrilinearField(const openvdb::FloatGrid& grid, std::optional<openvdb::CoordBBox> scan_box = std::nullopt)
        : accessor_(grid.getConstAccessor()), scan_box_(scan_box) {}

    const std::optional<openvdb::CoordBBox>& scan_box() const { return scan_box_; }

    FieldSample operator()(openvdb::Vec3d p) const {
        bool clamped[3] = {false, false, false};
        if (scan_box_) {
            for (int a = 0; a < 3; ++a) {
                const double lo = scan_box_->min()[a], hi = scan_box_->max()[a];
                if (p[a] < lo || p[a] > hi) {
                    p[a] = std::clamp(p[a], lo, hi);
                    clamped[a] = true;
                }
            }
        }
        FieldSample s = interpolate(p);
        for (int a = 0; a < 3; ++a)
            if (clamped[a]) s.gradient[a] = 0;
        return s;
    }

private:
    FieldSample interpolate(const openvdb::Vec3d& p) const {
        const openvdb::Coord base(int(std::floor(p[0])), int(std::floor(p[1])), int(std::floor(p[2])));
        const double tx = p[0] - base[0], ty = p[1] - base[1], tz = p[2] - base[2];
        double c[2][2][2];  // c[dx][dy][dz]
        using Leaf = openvdb::FloatTree::LeafNodeType;
        const openvdb::Coord local(base[0] & (Leaf::DIM - 1), base[1] & (Leaf::DIM - 1), base[2] & (Leaf::DIM - 1));
        const Leaf* leaf = local[0] + 1 < int(Leaf::DIM) && local[1] + 1 < int(Leaf::DIM) && local[2] + 1 < int(Leaf::DIM)
                               ? accessor_.probeConstLeaf(base)
                               : nullptr;
        // Most cells lie inside one leaf: their corners straight from its buffer, as getValue() reads them.
        const float* values = leaf ? leaf->buffer().data() + Leaf::coordToOffset(base) : nullptr;
        for (int dx = 0; dx < 2; ++dx)
            for (int dy = 0; dy < 2; ++dy)
                for (int dz = 0; dz < 2; ++dz)
                    c[dx][dy][dz] = values ? values[(dx << (2 * Leaf::LOG2DIM)) | (dy << Leaf::LOG2DIM) | dz]
                                           : accessor_.getValue(base.offsetBy(dx, dy, dz));
        // Interpolate along z, then y, then x, keeping the partial derivatives.
        double ez[2][2], dzv[2][2];
        for (int dx = 0; dx < 2; ++dx)
            for (int dy = 0; dy < 2; ++dy) {
                ez[dx][dy] = c[dx][dy][0] + tz * (c[dx][dy][1] - c[dx][dy][0]);
                dzv[dx][dy] = c[dx][dy][1] - c[dx][dy][0];
            }
        double ey[2], dyv[2], dzy[2];
        for (int dx = 0; dx < 2; ++dx) {
            ey[dx] = ez[dx][0] + ty * (ez[dx][1] - ez[dx][0]);
            dyv[dx] = ez[dx][1] - ez[dx][0];
            dzy[dx] = dzv[dx][0] + ty * (dzv[dx][1] - dzv[dx][0]);
        }
        FieldSample s;
        s.value = ey[0] + tx * (ey[1] - ey[0]);
        s.gradient = openvdb::Vec3d(ey[1] - ey[0], dyv[0] + tx * (dyv[1] - dyv[0]), dzy[0] + tx * (dzy[1] - dzy[0]));
        return s;
    }

    openvdb::FloatGrid::ConstAccessor accessor_;
    std::optional<openvdb::CoordBBox> scan_box_;
};

/// Newton's projection of @a point onto {field = iso} (steps along the gradient); empty when
/// it does not converge nearby. The point found is on the surface, so its distance to
/// @a point bounds the distance to the surface from above.
std::optional<openvdb::Vec3d> project_onto_isosurface(const TrilinearField& field, double iso, const openvdb::Vec3d& point);

/// The nearest point of {field = iso} to @a point that the closest-point iteration finds
/// (isosurface_search.cpp); empty when none within kTrilinearSearchVoxels.
std::optional<openvdb::Vec3d> closest_isosurface_point(const TrilinearField& field, double iso,
                                                       const openvdb::Vec3d& point);
/// The nearest point found on the boundary of the true solid: {field > iso} (or < iso when
/// !inside_above) cut by the scan box grown by half a voxel when the field has one (the
/// meshers' closing faces); the isosurface's nearest point when it lies in that box, or the
/// nearest point of a face whose samples are inside there. Empty when none was found.
std::optional<openvdb::Vec3d> closest_boundary_point(const TrilinearField& field, double iso, bool inside_above,
                                                     const openvdb::Vec3d& point);

}  // namespace vdbmesh::detail
