// Sample tangents for Dual Marching Cubes (see dmc_tangent.h): least-squares planes through
// the sample over the full 3x3x3 neighbourhood or over one of its 26 halves {p : p . u >= 0},
// u a neighbour direction, or one of its 8 octants, whichever fits; the normal matrices are
// fixed, so each fit is a sum and a 3x3 product.

#include "mesh/dmc_tangent.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace vdbmesh::detail {

namespace {

/// RMS residual (voxels) under which the full neighbourhood counts as planar: the plane of
/// central differences, second-order accurate on smooth surfaces, is kept.
constexpr double kSmooth = 0.02;
/// RMS residual (voxels) above which not even the best half is planar: no tangent.
constexpr double kPlanar = 0.05;
/// RMS residual (voxels) under which a tangent plane stands for the surface in
/// tangent_plane_distance(): the data is piecewise planar there (a phantom, a machined part
/// sampled finely), not merely smooth or noisy, where the trilinear field is the better guide.
constexpr double kExactPlane = 0.005;

struct Stencil {
    std::vector<int> points;  ///< neighbourhood indices, the centre excluded
    Eigen::Matrix3d inverse;  ///< of sum p p^T over the points
};

int index_of(int i, int j, int k) { return (i + 1) * 9 + (j + 1) * 3 + (k + 1); }

/// The stencil of the neighbours (not the centre) for which @a keep holds.
template <typename Keep>
Stencil make_stencil(Keep keep) {
    Stencil s;
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    for (int i = -1; i <= 1; ++i) {
        for (int j = -1; j <= 1; ++j) {
            for (int k = -1; k <= 1; ++k) {
                const Eigen::Vector3i p(i, j, k);
                if (p.isZero() || !keep(p)) continue;
                s.points.push_back(index_of(i, j, k));
                normal += p.cast<double>() * p.cast<double>().transpose();
            }
        }
    }
    s.inverse = normal.inverse();
    return s;
}

/// Stencil 0: the full neighbourhood; then the 26 halves p . u >= 0 (u a neighbour
/// direction), then the 8 octants (2x2x2 cubes holding the sample): a sample on the medial
/// axis of a corner (where three faces' pieces meet at 120 degrees) has no planar half, but
/// has planar octants.
std::vector<Stencil> make_stencils() {
    std::vector<Stencil> stencils = {make_stencil([](const Eigen::Vector3i&) { return true; })};
    for (int i = -1; i <= 1; ++i) {
        for (int j = -1; j <= 1; ++j) {
            for (int k = -1; k <= 1; ++k) {
                const Eigen::Vector3i u(i, j, k);
                if (!u.isZero()) stencils.push_back(make_stencil([&](const Eigen::Vector3i& p) { return p.dot(u) >= 0; }));
            }
        }
    }
    for (int octant = 0; octant < 8; ++octant) {
        const Eigen::Vector3i sign(octant & 1 ? 1 : -1, octant & 2 ? 1 : -1, octant & 4 ? 1 : -1);
        stencils.push_back(make_stencil([&](const Eigen::Vector3i& p) { return (p.array() * sign.array() >= 0).all(); }));
    }
    return stencils;
}

const std::vector<Stencil>& stencils() {
    static const std::vector<Stencil> all = make_stencils();
    return all;
}

struct Fit {
    Eigen::Vector3d gradient;
    double rms;
};

/// Per neighbour n: (delta p, delta^2) with delta = f_n - f_centre and p the offset; every
/// stencil's fit is a sum of these, so they are computed once per neighbourhood.
using Moments = std::array<std::array<double, 4>, 27>;

Moments moments_of(const Neighbourhood& f) {
    Moments m;
    for (int n = 0; n < 27; ++n) {
        const double delta = f[std::size_t(n)] - f[13];
        m[std::size_t(n)] = {delta * (n / 9 - 1), delta * (n / 3 % 3 - 1), delta * (n % 3 - 1), delta * delta};
    }
    return m;
}

Fit fit_plane(const Moments& m, const Stencil& s) {
    std::array<double, 4> sum{};
    for (int n : s.points) {
        for (std::size_t c = 0; c < 4; ++c) sum[c] += m[std::size_t(n)][c];
    }
    const Eigen::Vector3d b(sum[0], sum[1], sum[2]);
    const Eigen::Vector3d g = s.inverse * b;
    const double residual = std::max(sum[3] - g.dot(b), 0.0);
    return {g, std::sqrt(residual / double(s.points.size() - 3))};
}

Fit fit_plane(const Neighbourhood& f, const Stencil& s) { return fit_plane(moments_of(f), s); }

bool all_finite(const Neighbourhood& f) {
    return std::all_of(f.begin(), f.end(), [](double v) { return std::isfinite(v); });
}

/// The plane of sample_tangent() with its RMS residual; nothing where no part is planar.
std::optional<Fit> tangent_fit(const Neighbourhood& f) {
    if (!all_finite(f)) return std::nullopt;
    const std::vector<Stencil>& all = stencils();
    const Moments m = moments_of(f);
    const Fit full = fit_plane(m, all[0]);
    if (full.rms <= kSmooth) return full;
    Fit best = fit_plane(m, all[1]);
    for (std::size_t s = 2; s < all.size(); ++s) {
        const Fit part = fit_plane(m, all[s]);
        if (part.rms < best.rms) best = part;
    }
    if (best.rms > kPlanar) return std::nullopt;
    // Curvature alone leaves every half about as planar as the whole: keep the symmetric
    // (second-order) fit then; a crease leaves one half far more planar.
    return full.rms > 2.0 * best.rms ? best : full;
}

}  // namespace

std::optional<Point3d> sample_gradient(const Neighbourhood& f) {
    if (!all_finite(f)) return std::nullopt;
    const Eigen::Vector3d g = fit_plane(f, stencils()[0]).gradient;
    return Point3d{g(0), g(1), g(2)};
}

std::optional<Point3d> sample_tangent(const Neighbourhood& f) {
    const std::optional<Fit> fit = tangent_fit(f);
    if (!fit) return sample_gradient(f);
    return Point3d{fit->gradient(0), fit->gradient(1), fit->gradient(2)};
}

double tangent_plane_distance(const openvdb::FloatGrid::ConstAccessor& accessor, double iso, const openvdb::Vec3d& p) {
    const openvdb::Coord base = openvdb::Coord::floor(p);
    double nearest = std::numeric_limits<double>::infinity();
    for (int corner = 0; corner < 8; ++corner) {
        const openvdb::Coord sample = base.offsetBy(corner & 1, (corner >> 1) & 1, corner >> 2);
        Neighbourhood f;
        for (int n = 0; n < 27; ++n) {
            f[std::size_t(n)] = double(accessor.getValue(sample.offsetBy(n / 9 - 1, n / 3 % 3 - 1, n % 3 - 1))) - iso;
        }
        // In voxels: values over the sample's gradient magnitude (central differences).
        const double scale = fit_plane(f, stencils()[0]).gradient.norm();
        if (!(scale > 0.0)) continue;
        for (double& value : f) value /= scale;
        const std::optional<Fit> fit = tangent_fit(f);
        if (!fit || fit->rms > kExactPlane) continue;
        const double norm = fit->gradient.norm();
        if (!(norm > 0.0)) continue;
        const Eigen::Vector3d offset(p.x() - sample.x(), p.y() - sample.y(), p.z() - sample.z());
        nearest = std::min(nearest, std::abs(f[13] + fit->gradient.dot(offset)) / norm);
    }
    return nearest;
}

}  // namespace vdbmesh::detail
