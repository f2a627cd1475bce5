#pragma once
/// @file trilinear_field.h
/// @brief The grid stage's trilinear interpolant of a float grid in index space, with its
/// exact gradient (the derivative of the interpolating polynomial inside the cell holding the
/// point), and the search for the nearest point of its isosurface (isosurface_search.cpp):
/// the surface sample-based meshers approximate. compare.h measures
/// against it. Includes OpenVDB; in vdbmesh::detail: shared between the stages, not a stable API.

#include <openvdb/openvdb.h>

#include <algorithm>
#include <array>
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
        const std::array<bool, 3> clamped = clamp_into_box(p);
        FieldSample s = interpolate(p);
        for (int a = 0; a < 3; ++a)
            if (clamped[a]) s.gradient[a] = 0;
        return s;
    }

    /// operator()(p).value, bit for bit, without the gradient: the isosurface search steps
    /// along rays by values alone.
    double value(openvdb::Vec3d p) const {
        clamp_into_box(p);
        const Corners c = corners(p);
        const double ez[2][2] = {{lerp(c.v[0][0][0], c.v[0][0][1], c.t[2]), lerp(c.v[0][1][0], c.v[0][1][1], c.t[2])},
                                 {lerp(c.v[1][0][0], c.v[1][0][1], c.t[2]), lerp(c.v[1][1][0], c.v[1][1][1], c.t[2])}};
        return lerp(lerp(ez[0][0], ez[0][1], c.t[1]), lerp(ez[1][0], ez[1][1], c.t[1]), c.t[0]);
    }

private:
    /// The values at the 8 corners of the cell holding a point, v[dx][dy][dz], and the point's
    /// position in it.
    struct Corners {
        double v[2][2][2];
        double t[3];
    };

    static double lerp(double a, double b, double t) { return a + t * (b - a); }

    /// Moves @a p into the scan box (if any); returns which coordinates moved.
    std::array<bool, 3> clamp_into_box(openvdb::Vec3d& p) const {
        std::array<bool, 3> clamped = {false, false, false};
        if (!scan_box_) return clamped;
        for (int a = 0; a < 3; ++a) {
            const double lo = scan_box_->min()[a], hi = scan_box_->max()[a];
            if (p[a] < lo || p[a] > hi) {
                p[a] = std::clamp(p[a], lo, hi);
                clamped[a] = true;
            }
        }
        return clamped;
    }

    Corners corners(const openvdb::Vec3d& p) const {
        const openvdb::Coord base(int(std::floor(p[0])), int(std::floor(p[1])), int(std::floor(p[2])));
        Corners c;
        for (int a = 0; a < 3; ++a) c.t[a] = p[a] - base[a];
        // The search steps along rays by 1/16 voxel: most points fall in the previous cell.
        if (base != cached_base_) {
            fetch_corners(base, cached_values_);
            cached_base_ = base;
        }
        std::copy(&cached_values_[0][0][0], &cached_values_[0][0][0] + 8, &c.v[0][0][0]);
        return c;
    }

    void fetch_corners(const openvdb::Coord& base, double v[2][2][2]) const {
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
                    v[dx][dy][dz] = values ? values[(dx << (2 * Leaf::LOG2DIM)) | (dy << Leaf::LOG2DIM) | dz]
                                           : accessor_.getValue(base.offsetBy(dx, dy, dz));
    }

    FieldSample interpolate(const openvdb::Vec3d& p) const {
        const Corners corner = corners(p);
        const auto& c = corner.v;
        const double tx = corner.t[0], ty = corner.t[1], tz = corner.t[2];
        // Interpolate along z, then y, then x, keeping the partial derivatives.
        double ez[2][2], dzv[2][2];
        for (int dx = 0; dx < 2; ++dx)
            for (int dy = 0; dy < 2; ++dy) {
                ez[dx][dy] = lerp(c[dx][dy][0], c[dx][dy][1], tz);
                dzv[dx][dy] = c[dx][dy][1] - c[dx][dy][0];
            }
        double ey[2], dyv[2], dzy[2];
        for (int dx = 0; dx < 2; ++dx) {
            ey[dx] = lerp(ez[dx][0], ez[dx][1], ty);
            dyv[dx] = ez[dx][1] - ez[dx][0];
            dzy[dx] = lerp(dzv[dx][0], dzv[dx][1], ty);
        }
        FieldSample s;
        s.value = lerp(ey[0], ey[1], tx);
        s.gradient = openvdb::Vec3d(ey[1] - ey[0], lerp(dyv[0], dyv[1], tx), lerp(dzy[0], dzy[1], tx));
        return s;
    }

    openvdb::FloatGrid::ConstAccessor accessor_;
    std::optional<openvdb::CoordBBox> scan_box_;
    mutable openvdb::Coord cached_base_{openvdb::Coord::max()};  ///< no cell's: nothing cached yet
    mutable double cached_values_[2][2][2] = {};
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
