// Surface-to-surface distances (DESIGN.md section 6): points sampled uniformly by area on one
// surface (a triangle chosen with probability proportional to its area, then a uniform point
// in it by the square-root mapping of Osada et al., "Shape distributions", ACM TOG 2002),
// measured exactly to the closest point of the other mesh through a BVH (geometry.h),
// or by an analytic signed-distance function. Sample k comes from a counter-based generator
// (SplitMix64 of the seed and k), so results do not depend on the thread count.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "analysis/block_reduce.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"

namespace vdbmesh {
namespace {

using detail::Point3;

constexpr std::uint64_t kSeed = 0x2545f4914f6cdd1dULL;
constexpr std::size_t kBlock = 4096;

/// SplitMix64 (S. Vigna): a well-mixed 64-bit value from a counter.
std::uint64_t split_mix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

/// A uniform double in [0, 1) from 53 random bits.
double unit(std::uint64_t bits) { return double(bits >> 11) * (1.0 / 9007199254740992.0); }

/// Draws points uniformly by area on a mesh.
class AreaSampler {
public:
    explicit AreaSampler(const Mesh& mesh) : mesh_(mesh), cumulative_(mesh.triangles.size()) {
        double total = 0;
        for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
            total += triangle_area(mesh.triangles[i]);
            cumulative_[i] = total;
        }
        if (!(total > 0)) throw Error("distance: a mesh has no triangle of positive area to sample");
    }

    Point3 sample(std::uint64_t stream, std::size_t k) const {
        const std::uint64_t base = split_mix(kSeed ^ stream) + 3 * std::uint64_t(k);
        const double pick = unit(split_mix(base)) * cumulative_.back();
        const std::size_t i = std::min(std::size_t(std::upper_bound(cumulative_.begin(), cumulative_.end(), pick) -
                                                   cumulative_.begin()),
                                       cumulative_.size() - 1);
        const double root = std::sqrt(unit(split_mix(base + 1))), v = unit(split_mix(base + 2));
        const auto& t = mesh_.triangles[i];
        const double wa = 1 - root, wb = root * (1 - v), wc = root * v;
        Point3 p{};
        for (int k3 = 0; k3 < 3; ++k3) {
            p[k3] = wa * mesh_.vertices[t[0]][k3] + wb * mesh_.vertices[t[1]][k3] + wc * mesh_.vertices[t[2]][k3];
        }
        return p;
    }

private:
    double triangle_area(const std::array<std::uint32_t, 3>& t) const {
        const auto& a = mesh_.vertices[t[0]];
        const auto& b = mesh_.vertices[t[1]];
        const auto& c = mesh_.vertices[t[2]];
        const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
        const double w[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
        const double x = u[1] * w[2] - u[2] * w[1], y = u[2] * w[0] - u[0] * w[2], z = u[0] * w[1] - u[1] * w[0];
        return 0.5 * std::sqrt(x * x + y * y + z * z);
    }

    const Mesh& mesh_;
    std::vector<double> cumulative_;
};

/// One direction's distances: their count, maximum, sum and sum of squares.
template <class DistanceOf>
detail::ValueStats measure(std::size_t count, DistanceOf distance_of) {
    return detail::block_stats(count, kBlock, [&](std::size_t k, detail::ValueStats& stats) { stats.add(distance_of(k)); });
}

std::vector<std::uint32_t> all_triangles(const Mesh& mesh) {
    std::vector<std::uint32_t> all(mesh.triangles.size());
    std::iota(all.begin(), all.end(), 0u);
    return all;
}

DistanceReport combine(const detail::ValueStats& ab, const detail::ValueStats& ba) {
    DistanceReport report;
    report.max_a_to_b = ab.count ? ab.max : 0.0;
    report.max_b_to_a = ba.count ? ba.max : 0.0;
    report.hausdorff = std::max(report.max_a_to_b, report.max_b_to_a);
    report.mean_a_to_b = ab.count ? ab.sum / double(ab.count) : 0.0;
    report.mean_b_to_a = ba.count ? ba.sum / double(ba.count) : 0.0;
    report.mean = ba.count ? 0.5 * (report.mean_a_to_b + report.mean_b_to_a) : report.mean_a_to_b;
    const std::size_t count = ab.count + ba.count;
    report.rms = count ? std::sqrt((ab.sum_squares + ba.sum_squares) / double(count)) : 0.0;
    return report;
}

}  // namespace

DistanceReport mesh_distance(const Mesh& a, const Mesh& b, std::size_t samples_per_mesh) {
    detail::check_indices(a);
    detail::check_indices(b);
    const AreaSampler sample_a(a), sample_b(b);
    const detail::TriangleBvh tree_a(a, all_triangles(a)), tree_b(b, all_triangles(b));
    const detail::ValueStats ab = measure(samples_per_mesh, [&](std::size_t k) {
        return std::sqrt(tree_b.closest_point(sample_a.sample(0, k)).distance_squared);
    });
    const detail::ValueStats ba = measure(samples_per_mesh, [&](std::size_t k) {
        return std::sqrt(tree_a.closest_point(sample_b.sample(1, k)).distance_squared);
    });
    return combine(ab, ba);
}

std::vector<std::array<double, 3>> sample_surface(const Mesh& mesh, std::size_t count) {
    detail::check_indices(mesh);
    const AreaSampler sampler(mesh);
    std::vector<std::array<double, 3>> points(count);
    for (std::size_t k = 0; k < count; ++k) points[k] = sampler.sample(2, k);
    return points;
}

DistanceReport mesh_distance(const Mesh& mesh, const std::function<double(double, double, double)>& signed_distance,
                             std::size_t samples, const std::vector<std::array<double, 3>>& surface_points) {
    detail::check_indices(mesh);
    const AreaSampler sampler(mesh);
    const detail::ValueStats to_surface = measure(samples, [&](std::size_t k) {
        const Point3 p = sampler.sample(0, k);
        return std::fabs(signed_distance(p[0], p[1], p[2]));
    });
    detail::ValueStats to_mesh;
    if (!surface_points.empty()) {
        const detail::TriangleBvh tree(mesh, all_triangles(mesh));
        to_mesh = measure(surface_points.size(), [&](std::size_t k) {
            return std::sqrt(tree.closest_point(surface_points[k]).distance_squared);
        });
    }
    return combine(to_surface, to_mesh);
}

}  // namespace vdbmesh
