// The 3D QEF's minimiser, by an eigen-decomposition of A^T A around the points' mean.

#include "mesh/dc_qef.h"

#include <Eigen/Eigenvalues>

#include <algorithm>

namespace vdbmesh::detail {

namespace {

/// Eigenvalues below this share of the largest are treated as zero (singular values below
/// about 0.1 of the largest, as Dual Contouring does), so noise in nearly parallel normals
/// does not throw the vertex along the surface.
constexpr double kRelativeEigenvalueFloor = 0.01;

/// A^T A as a matrix, from its six entries xx, xy, xz, yy, yz, zz.
Eigen::Matrix3d normal_matrix(const std::array<double, 6>& a) {
    Eigen::Matrix3d ata;
    ata << a[0], a[1], a[2], a[1], a[3], a[4], a[2], a[4], a[5];
    return ata;
}

}  // namespace

double Qef3::residual(const Point3d& x) const {
    const double axx = ata_[0] * x[0] + ata_[1] * x[1] + ata_[2] * x[2];
    const double axy = ata_[1] * x[0] + ata_[3] * x[1] + ata_[4] * x[2];
    const double axz = ata_[2] * x[0] + ata_[4] * x[1] + ata_[5] * x[2];
    const double xtax = x[0] * axx + x[1] * axy + x[2] * axz;
    return std::max(0.0, xtax - 2 * (x[0] * atb_[0] + x[1] * atb_[1] + x[2] * atb_[2]) + btb_);
}

int Qef3::conditioned_directions(double share) const {
    if (count_ == 0) return 0;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
    eigen.computeDirect(normal_matrix(ata_), Eigen::EigenvaluesOnly);
    const Eigen::Vector3d values = eigen.eigenvalues();
    const double floor = share * values.cwiseAbs().maxCoeff();
    int directions = 0;
    for (int i = 0; i < 3; ++i) directions += values[i] > floor && values[i] > 0;
    return directions;
}

Point3d Qef3::minimiser() const {
    const Eigen::Matrix3d ata = normal_matrix(ata_);
    const Eigen::Vector3d mean(point_sum_[0] / count_, point_sum_[1] / count_, point_sum_[2] / count_);
    const Eigen::Vector3d rhs = Eigen::Vector3d(atb_[0], atb_[1], atb_[2]) - ata * mean;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
    eigen.computeDirect(ata);  // closed form for 3x3: several times faster than the iterative solver
    const Eigen::Vector3d values = eigen.eigenvalues();
    const double floor = kRelativeEigenvalueFloor * values.cwiseAbs().maxCoeff();
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i) {
        if (values[i] > floor && values[i] > 0) {
            const Eigen::Vector3d v = eigen.eigenvectors().col(i);
            step += v * (v.dot(rhs) / values[i]);
        }
    }
    const Eigen::Vector3d x = mean + step;
    return {x[0], x[1], x[2]};
}

}  // namespace vdbmesh::detail
