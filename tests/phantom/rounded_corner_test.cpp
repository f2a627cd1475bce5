// Issue 9, points 3 and 4 on the rotated cube: the exact corners of the phantom lie more than
// 0.55 voxel from the trilinear isosurface of its samples (a dense search put them at 0.64-0.71).
// A mesh within 0.2 voxel of a corner (point 4 at --error 0.1) is then more than 0.35 voxel from
// that isosurface, beyond the 2E = 0.2 of point 3, so no mesh meets both there (docs/dmc.md,
// "Session 12"). With 0.6 the lattice below cannot decide: its points reach 0.62, where the
// isosurface nearly is.
//
// Judged without the meshers' code or the isosurface search: the trilinear interpolant of
// phantom_sample() is evaluated here on a lattice around each corner. The density is an affine
// function of the signed distance with slope 1 / (2 blur), so neighbouring samples differ by at
// most 1 / (2 blur) and each partial derivative of the interpolant is bounded by it: within a
// lattice cell of side h the interpolant moves by at most sqrt(3) / (2 blur) * h * sqrt(3) / 2
// from its value at the nearest lattice point. Where every lattice point within r + h of the
// corner is farther than that from the isovalue and on the same side, no point of the
// isosurface lies within r.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <iostream>

#include "vdbmesh/phantom.h"

namespace vdbmesh {
namespace {

using Vec3 = std::array<double, 3>;

constexpr double kPi = 3.14159265358979323846;

/// Rz(c) * Ry(b) * Rx(a) of the phantom's rotation_degrees (include/vdbmesh/phantom.h), applied to @a v.
Vec3 rotate(const std::array<double, 3>& degrees, const Vec3& v) {
    const double a = degrees[0] * kPi / 180, b = degrees[1] * kPi / 180, c = degrees[2] * kPi / 180;
    const Vec3 x = {v[0], std::cos(a) * v[1] - std::sin(a) * v[2], std::sin(a) * v[1] + std::cos(a) * v[2]};
    const Vec3 y = {std::cos(b) * x[0] + std::sin(b) * x[2], x[1], -std::sin(b) * x[0] + std::cos(b) * x[2]};
    return {std::cos(c) * y[0] - std::sin(c) * y[1], std::sin(c) * y[0] + std::cos(c) * y[1], y[2]};
}

/// The trilinear interpolant of the phantom's samples at @a p.
double trilinear(const PhantomSpec& spec, const Vec3& p) {
    const std::int64_t i = std::int64_t(std::floor(p[0])), j = std::int64_t(std::floor(p[1])), k = std::int64_t(std::floor(p[2]));
    const double tx = p[0] - double(i), ty = p[1] - double(j), tz = p[2] - double(k);
    double value = 0;
    for (int c = 0; c < 8; ++c) {
        const int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
        const double w = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty) * (dz ? tz : 1 - tz);
        value += w * phantom_sample(spec, i + dx, j + dy, k + dz);
    }
    return value;
}

TEST(RoundedCornerTest, RotatedCubeCornersLieFarFromTheTrilinearIsosurface) {
    const PhantomSpec spec = phantom_preset("rotated-cube", {128, 128, 128});
    ASSERT_GT(spec.blur, 0.0);
    const double half_side = spec.side / 2;
    const std::array<double, 3> centre = spec.centre_or_default();
    constexpr double kRadius = 0.55;  // the claim: no isosurface point within this of a corner
    constexpr double kStep = 0.02;    // lattice spacing (voxels)
    // How far the interpolant can move from a lattice point within its lattice cell.
    const double slack = std::sqrt(3.0) / (2 * spec.blur) * kStep * std::sqrt(3.0) / 2;
    const int steps = int(std::ceil((kRadius + kStep) / kStep));
    double nearest_checked = 1e9;
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 local = {(corner & 1 ? 1 : -1) * half_side, (corner & 2 ? 1 : -1) * half_side, (corner & 4 ? 1 : -1) * half_side};
        const Vec3 r = rotate(spec.rotation_degrees, local);
        const Vec3 p = {centre[0] + r[0], centre[1] + r[1], centre[2] + r[2]};
        // The point is the solid's corner: on its surface, with the solid on one side of it
        // along the diagonal and none on the other.
        ASSERT_NEAR(phantom_signed_distance(spec, p[0], p[1], p[2]), 0.0, 1e-9);
        const auto along_diagonal = [&](double s) {
            return phantom_signed_distance(spec, centre[0] + s * r[0], centre[1] + s * r[1], centre[2] + s * r[2]);
        };
        ASSERT_LT(along_diagonal(0.99), 0.0);
        ASSERT_GT(along_diagonal(1.01), 0.0);
        const bool outside = trilinear(spec, p) < 0.5;  // density 1 inside
        for (int a = -steps; a <= steps; ++a) {
            for (int b = -steps; b <= steps; ++b) {
                for (int c = -steps; c <= steps; ++c) {
                    const double d = kStep * std::sqrt(double(a * a + b * b + c * c));
                    if (d > kRadius + kStep) continue;
                    const double f = trilinear(spec, {p[0] + a * kStep, p[1] + b * kStep, p[2] + c * kStep});
                    ASSERT_EQ(f < 0.5, outside) << "corner " << corner << ": the isosurface passes within " << d;
                    ASSERT_GT(std::abs(f - 0.5), slack) << "corner " << corner << " at " << d;
                    nearest_checked = std::min(nearest_checked, std::abs(f - 0.5));
                }
            }
        }
    }
    std::cout << "[ figures  ] no isosurface point within " << kRadius << " voxel of any corner; smallest |f - iso| on the lattice "
              << nearest_checked << " (slack " << slack << ")\n";
}

}  // namespace
}  // namespace vdbmesh
