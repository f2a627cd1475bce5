#pragma once
// Private: the 3D quadratic error function of Dual Contouring (Ju, Losasso, Schaefer and Warren
// 2002): for surface points p_i with unit normals n_i, E(x) = sum (n_i . (x - p_i))^2. Kept as
// A^T A, A^T b, b^T b and the points' sum, so the QEFs of children add.

#include <array>

#include "mesh/edge_crossing.h"

namespace vdbmesh::detail {

class Qef3 {
public:
    void add_plane(const Point3d& point, const Point3d& normal);
    void add(const Qef3& other);
    int count() const { return count_; }
    /// E(x): the sum of the squared distances from @a x to the planes.
    double residual(const Point3d& x) const;

    /// The minimiser nearest the points' mean (a truncated pseudo-inverse: directions the
    /// normals do not pin down stay at the mean, so flat and ridge cells keep their vertex
    /// on the surface's middle). Requires count() > 0.
    Point3d minimiser() const;

    /// How many directions the planes pin down: the eigenvalues of A^T A above @a share of the
    /// largest (0 without planes). Two on a sharp edge, three at a corner, one on a flat or
    /// gently curved surface (`--sharp`: is_sharp_feature()).
    int conditioned_directions(double share) const;

private:
    std::array<double, 6> ata_{};  ///< xx, xy, xz, yy, yz, zz
    std::array<double, 3> atb_{};
    std::array<double, 3> point_sum_{};
    double btb_ = 0;
    int count_ = 0;
};

/// `--sharp` (MeshOptions::sharp, docs/dmc.md "Sharp features"): a cell whose QEF pins down two
/// or three directions, each eigenvalue of A^T A above this share of the largest, holds an edge
/// or a corner. Two faces meeting at 90 degrees give equal eigenvalues, so the share only has to
/// tell an edge whose one face the cell barely clips (a few of its crossings against many) and
/// curved surfaces: normals spread evenly over an angle a give about a^2 / 12, so 0.1 takes a
/// spread of 63 degrees or more within one cell.
inline constexpr double kSharpFeatureShare = 0.1;

/// `--sharp`: how far (voxels) beyond the error a feature cell's vertex may leave the trilinear
/// isosurface and the tangent planes of its crossings, where the bound of DC without it rounds the
/// edges and corners (the exact corners of the phantoms lie 0.64-0.71 voxel from the trilinear
/// isosurface: RoundedCornerTest).
inline constexpr double kSharpReach = 1.0;

/// Whether @a qef holds a sharp edge or corner (kSharpFeatureShare).
inline bool is_sharp_feature(const Qef3& qef) { return qef.conditioned_directions(kSharpFeatureShare) >= 2; }

// Inline: the octree adds a plane per crossing and sums every cell's children, in loops the
// compiler can then unroll.
inline void Qef3::add_plane(const Point3d& p, const Point3d& n) {
    const double d = n[0] * p[0] + n[1] * p[1] + n[2] * p[2];
    ata_[0] += n[0] * n[0];
    ata_[1] += n[0] * n[1];
    ata_[2] += n[0] * n[2];
    ata_[3] += n[1] * n[1];
    ata_[4] += n[1] * n[2];
    ata_[5] += n[2] * n[2];
    for (int a = 0; a < 3; ++a) {
        atb_[a] += n[a] * d;
        point_sum_[a] += p[a];
    }
    btb_ += d * d;
    ++count_;
}

inline void Qef3::add(const Qef3& other) {
    for (int i = 0; i < 6; ++i) ata_[i] += other.ata_[i];
    for (int a = 0; a < 3; ++a) {
        atb_[a] += other.atb_[a];
        point_sum_[a] += other.point_sum_[a];
    }
    btb_ += other.btb_;
    count_ += other.count_;
}

}  // namespace vdbmesh::detail
