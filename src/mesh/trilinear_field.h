#pragma once
// Private: the trilinear interpolant of a float grid in index space, with its exact gradient
// (the derivative of the interpolating polynomial inside the cell holding the point).

#include <openvdb/openvdb.h>

#include <cmath>
#include <optional>

namespace vdbmesh::detail {

/// Value and gradient of the interpolant at a point (index space).
struct FieldSample {
    double value = 0;
    openvdb::Vec3d gradient{0, 0, 0};
};

/// Not thread-safe (it caches tree nodes in an accessor): one per thread.
class TrilinearField {
public:
    explicit TrilinearField(const openvdb::FloatGrid& grid) : accessor_(grid.getConstAccessor()) {}

    FieldSample operator()(const openvdb::Vec3d& p) const {
        const openvdb::Coord base(int(std::floor(p[0])), int(std::floor(p[1])), int(std::floor(p[2])));
        const double tx = p[0] - base[0], ty = p[1] - base[1], tz = p[2] - base[2];
        double c[2][2][2];  // c[dx][dy][dz]
        for (int dx = 0; dx < 2; ++dx)
            for (int dy = 0; dy < 2; ++dy)
                for (int dz = 0; dz < 2; ++dz)
                    c[dx][dy][dz] = accessor_.getValue(base.offsetBy(dx, dy, dz));
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

private:
    openvdb::FloatGrid::ConstAccessor accessor_;
};

/// The nearest point of {field = iso} to @a point that the closest-point iteration finds
/// (isosurface_distance.cpp); empty when none within kIsosurfaceSearchVoxels.
std::optional<openvdb::Vec3d> closest_isosurface_point(const TrilinearField& field, double iso,
                                                       const openvdb::Vec3d& point);
/// distance_to_trilinear_isosurface() (compare.h) with the caller's per-thread field.
std::optional<double> distance_to_isosurface(const TrilinearField& field, double iso, const openvdb::Vec3d& point);

}  // namespace vdbmesh::detail
