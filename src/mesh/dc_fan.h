#pragma once
// Private: the accuracy tests a merged cell of intersection-free contouring must pass, shared
// by the merges within a block (dc_octree.cpp) and across blocks (dc_coarse_merge.cpp).

#include <array>

#include "mesh/edge_crossing.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh::detail {

/// The fan a merged cell will be, as far as its accuracy is concerned: its vertex joined to
/// each face's trace, the trace taken as the chord between its two ends through its middle.
class IfcFan {
public:
    explicit IfcFan(const Point3d& vertex) : vertex_(vertex) {}
    /// Adds the two triangles over the chord from @a a to @a b on one face.
    void add_chord(const Point3d& a, const Point3d& b);
    /// Whether @a p lies within @a distance of some triangle of the fan. The triangle that was
    /// near last time is tried first: points are asked in order along the cell's grid lines,
    /// so it is usually near again (the answer does not depend on the order).
    bool near(const Point3d& p, double distance);
    /// Calls @a visit(point) at the points of a lattice of @a divisions steps per side on each
    /// triangle, its corners included; stops when @a visit returns false, and returns false then.
    template <typename Visit>
    bool sample(int divisions, Visit&& visit) const {
        for (int t = 0; t < count_; ++t) {
            const Triangle3& tri = triangles_[t];
            for (int i = 0; i <= divisions; ++i) {
                for (int j = 0; i + j <= divisions; ++j) {
                    const double a = double(i) / divisions, b = double(j) / divisions;
                    Point3d p;
                    for (int k = 0; k < 3; ++k) p[k] = tri[0][k] + a * (tri[1][k] - tri[0][k]) + b * (tri[2][k] - tri[0][k]);
                    if (!visit(p)) return false;
                }
            }
        }
        return true;
    }

private:
    Point3d vertex_;
    std::array<Triangle3, 12> triangles_;
    int count_ = 0;
    int last_near_ = 0;
};

/// Whether the surface crosses a face of a merged cell of @a size voxels widely, its trace there
/// being the chord from @a a to @a b: at least the cell's size. Where it only clips the face by a
/// corner, the triangles over that face join the cell's far vertex to a short chord (the chord
/// itself, or a unit face's segment next to a Marching Cubes cell) and are slivers unless the
/// cell across is as large (dual_contouring.cpp, split_clipped_blocks()).
inline bool ifc_chord_spans_face(const Point3d& a, const Point3d& b, int size) {
    return squared_distance(a, b) >= double(size) * size;
}

/// First-order distance |f - iso| / |grad f| (voxels) of the trilinear interpolant of the 8
/// corner values of a unit cell (corner c at (c & 1, (c >> 1) & 1, c >> 2)) at the local
/// position @a t in [0, 1]^3; 0 where a value is not finite (beyond the scan box).
double trilinear_surface_distance(const std::array<double, 8>& corner_values, const std::array<double, 3>& t, double iso);

/// The same at point @a p, in the unit cell whose minimum corner is @a cell (both in one
/// frame, global or a block's), its corner values read by @a sample(x, y, z).
template <class Sample>
double cell_surface_distance(const Point3d& p, const std::array<int, 3>& cell, Sample&& sample, double iso) {
    std::array<double, 8> values;
    for (int c = 0; c < 8; ++c) values[c] = sample(cell[0] + (c & 1), cell[1] + ((c >> 1) & 1), cell[2] + (c >> 2));
    return trilinear_surface_distance(values, {p[0] - cell[0], p[1] - cell[1], p[2] - cell[2]}, iso);
}

}  // namespace vdbmesh::detail
