// The 4D QEF of Dual Marching Cubes (see dmc_qef.h), solved with Eigen's self-adjoint
// eigensolver: the pseudo-inverse drops eigenvalues below kTruncation times the largest, as
// Lindstrom's and Ju et al.'s QEF solvers do, which keeps the solution at the mass point
// along directions the tangent planes leave free (flat or singly curved surfaces).

#include "mesh/dmc_qef.h"

#include <Eigen/Dense>

#include <algorithm>

namespace vdbmesh::detail {

namespace {

constexpr double kTruncation = 0.02;

/// Index of (row, col), row <= col, in the upper triangle of a 5x5 matrix stored row by row.
constexpr int upper(int row, int col) { return row * 5 - row * (row - 1) / 2 + (col - row); }

/// Value (scaled units: voxels) the vertex is moved to, on the side of the samples' mean,
/// along directions the planes leave free.
constexpr double kSurfaceMargin = 0.02;
/// Weight of the value against the position when choosing among equally good minimisers.
constexpr double kValueWeight = 1e4;
/// Free directions whose value component is below this (unit vectors) leave the value fixed:
/// no ridge.
constexpr double kRidgeSlope = 0.1;

/// Moves the minimiser @a y along the free directions (eigenvectors @a v whose @a inverse is 0)
/// to value +-kSurfaceMargin, as near the mass point as possible. Where the planes leave the
/// value free, the graph of the field is a ridge of equally good minimisers: inside a convex
/// corner or edge of a distance-like field the planes of the faces meet all along the medial
/// axis, and the mass point picks a vertex deep inside whose value, interpolated linearly
/// towards the neighbours, cuts the corner. The point of the ridge at the isovalue is the
/// feature itself; the margin keeps the vertex strictly on its side, so the signs of the dual
/// cells' corners stay those of the mass point. Where the feature lies outside the cell's box
/// [lo, hi] (a cell next to a medial surface), the vertex stays where it was.
Eigen::Vector4d on_surface(const Eigen::Vector4d& y, const Eigen::Vector4d& mass, const Eigen::Matrix4d& v,
                           const Eigen::Vector4d& inverse, const Point3d& lo, const Point3d& hi) {
    Eigen::Matrix<double, 4, Eigen::Dynamic> free(4, 0);
    for (int i = 0; i < 4; ++i) {
        if (inverse(i) == 0.0) {
            free.conservativeResize(Eigen::NoChange, free.cols() + 1);
            free.col(free.cols() - 1) = v.col(i);
        }
    }
    // One plane (a flat face) has no ridge: its vertex stays at the mass point, its value
    // well away from the isovalue, so crossings towards it land next to feature vertices.
    if (free.cols() == 0 || free.cols() >= 3 || mass(3) == 0.0 || free.row(3).norm() < kRidgeSlope) return y;
    const Eigen::Vector4d target(mass(0), mass(1), mass(2), mass(3) > 0.0 ? kSurfaceMargin : -kSurfaceMargin);
    const Eigen::Vector4d weight(1.0, 1.0, 1.0, kValueWeight);
    const Eigen::MatrixXd normal = free.transpose() * weight.asDiagonal() * free;
    const Eigen::VectorXd c = normal.ldlt().solve(free.transpose() * weight.asDiagonal() * (target - y));
    const Eigen::Vector4d moved = y + free * c;
    for (int k = 0; k < 3; ++k) {
        if (moved(k) < lo[std::size_t(k)] || moved(k) > hi[std::size_t(k)]) return y;
    }
    return moved;
}

}  // namespace

void Qef4::add_sample(const Point3d& x, double f, const Point3d& g) {
    const double weight = 1.0 / (1.0 + g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    // Row [a | -b] with a = (g, -1) and b = g . x - f: residual a . (x, w) - b.
    const std::array<double, 5> row = {g[0], g[1], g[2], -1.0, f - (g[0] * x[0] + g[1] * x[1] + g[2] * x[2])};
    for (int r = 0; r < 5; ++r) {
        for (int c = r; c < 5; ++c) m_[std::size_t(upper(r, c))] += weight * row[std::size_t(r)] * row[std::size_t(c)];
    }
    mass_[0] += x[0];
    mass_[1] += x[1];
    mass_[2] += x[2];
    mass_[3] += f;
    ++count_;
}

void Qef4::add(const Qef4& other) {
    for (std::size_t i = 0; i < m_.size(); ++i) m_[i] += other.m_[i];
    for (std::size_t i = 0; i < 4; ++i) mass_[i] += other.mass_[i];
    count_ += other.count_;
}

double Qef4::evaluate(const std::array<double, 4>& y) const {
    const std::array<double, 5> z = {y[0], y[1], y[2], y[3], 1.0};
    double e = 0.0;
    for (int r = 0; r < 5; ++r) {
        for (int c = r; c < 5; ++c) {
            const double term = m_[std::size_t(upper(r, c))] * z[std::size_t(r)] * z[std::size_t(c)];
            e += r == c ? term : 2.0 * term;
        }
    }
    return std::max(e, 0.0);
}

Qef4::Solution Qef4::solve(const Point3d& lo, const Point3d& hi) const {
    Eigen::Matrix4d ata;
    Eigen::Vector4d atb;
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) ata(r, c) = m_[std::size_t(upper(std::min(r, c), std::max(r, c)))];
        atb(r) = -m_[std::size_t(upper(r, 4))];
    }
    const Eigen::Vector4d mass = Eigen::Vector4d(mass_[0], mass_[1], mass_[2], mass_[3]) / double(std::max(count_, 1));
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(ata);
    const Eigen::Vector4d lambda = eigen.eigenvalues();
    const double largest = lambda.cwiseAbs().maxCoeff();
    Eigen::Vector4d inverse = Eigen::Vector4d::Zero();
    for (int i = 0; i < 4; ++i) {
        if (largest > 0.0 && lambda(i) > kTruncation * largest) inverse(i) = 1.0 / lambda(i);
    }
    const Eigen::Matrix4d& v = eigen.eigenvectors();
    const Eigen::Vector4d y = on_surface(mass + v * inverse.asDiagonal() * v.transpose() * (atb - ata * mass), mass, v, inverse, lo, hi);

    std::array<double, 4> best = {y(0), y(1), y(2), y(3)};
    bool clamped = false;
    for (std::size_t k = 0; k < 3; ++k) {
        const double inside = std::clamp(best[k], lo[k], hi[k]);
        clamped = clamped || inside != best[k];
        best[k] = inside;
    }
    if (clamped && ata(3, 3) > 0.0) {
        // Best value for the clamped position: dE/dw = 0.
        best[3] = (atb(3) - ata(3, 0) * best[0] - ata(3, 1) * best[1] - ata(3, 2) * best[2]) / ata(3, 3);
    }
    return {{best[0], best[1], best[2]}, best[3], evaluate(best)};
}

}  // namespace vdbmesh::detail
