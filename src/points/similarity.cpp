// Similarity of two solids (the method's chapter 3.5): coarse alignment by centroids, size
// and principal axes with every proper assignment of axes and signs, then Levenberg-Marquardt
// on scale, rotation and translation minimising the sum of squared field values of the
// transformed sample points in the reference's field.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "vdbmesh/error.h"
#include "vdbmesh/points.h"

namespace vdbmesh {

namespace {

struct Frame {
    Eigen::Vector3d centroid;
    Eigen::Matrix3d axes;  // columns: principal axes, largest variance first
    double size = 1;       // RMS distance from the centroid
};

Frame frame_of(const std::vector<Vec3d>& points) {
    Frame f;
    f.centroid.setZero();
    for (const Vec3d& p : points) f.centroid += Eigen::Vector3d(p[0], p[1], p[2]);
    f.centroid /= double(points.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const Vec3d& p : points) {
        const Eigen::Vector3d d = Eigen::Vector3d(p[0], p[1], p[2]) - f.centroid;
        cov += d * d.transpose();
    }
    cov /= double(points.size());
    f.size = std::sqrt(std::max(cov.trace(), 1e-300));
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
    for (int k = 0; k < 3; ++k) f.axes.col(k) = solver.eigenvectors().col(2 - k);
    return f;
}

Eigen::Matrix3d rotation_of(const Eigen::Vector3d& w) {
    const double angle = w.norm();
    if (angle < 1e-15) return Eigen::Matrix3d::Identity();
    return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

struct Pose {
    double log_scale = 0;
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    Eigen::Vector3d apply(const Eigen::Vector3d& x) const { return std::exp(log_scale) * (rotation * x) + translation; }
};

/// Mean squared field value over @a points, in units of the reference's size squared.
double energy(const RbfField& field, const std::vector<Eigen::Vector3d>& points, const Pose& pose, double size) {
    std::vector<double> r(points.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 64), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
            const Eigen::Vector3d y = pose.apply(points[i]);
            const double v = field.value({y.x(), y.y(), y.z()}) / size;
            r[i] = v * v;
        }
    });
    double s = 0;
    for (double v : r) s += v;  // serial: the same sum for any thread count
    return s / double(points.size());
}

/// Levenberg-Marquardt on (log scale, rotation increment, translation).
/// The scale may move from the coarse estimate (the ratio of RMS sizes) only at a cost:
/// without it every sample would shrink onto one spot of the reference's surface.
constexpr double kScaleWeight = 0.1;

Pose refine(const RbfField& field, const std::vector<Eigen::Vector3d>& points, Pose pose, double size, int iterations,
            bool allow_scale, int& used) {
    const std::size_t n = points.size();
    const double scale0 = pose.log_scale;
    auto cost = [&](const Pose& p) {
        const double d = p.log_scale - scale0;
        return energy(field, points, p, size) + kScaleWeight * kScaleWeight * d * d;
    };
    double lambda = 1e-3;
    double current = cost(pose);
    for (used = 0; used < iterations; ++used) {
        std::vector<Eigen::Matrix<double, 7, 1>> rows(n);
        std::vector<double> res(n);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 64), [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t i = range.begin(); i < range.end(); ++i) {
                const Eigen::Vector3d y = pose.apply(points[i]);
                const Vec3d yy{y.x(), y.y(), y.z()};
                res[i] = field.value(yy) / size;
                const Vec3d g3 = field.gradient(yy);
                const Eigen::Vector3d g(g3[0] / size, g3[1] / size, g3[2] / size);
                const Eigen::Vector3d z = y - pose.translation;  // s R x
                Eigen::Matrix<double, 7, 1> row;
                row[0] = allow_scale ? g.dot(z) : 0.0;
                const Eigen::Vector3d c = z.cross(g);  // d/dw of g . (w x z) = g . (w x z) = w . (z x g)
                row[1] = c.x(), row[2] = c.y(), row[3] = c.z();
                row[4] = g.x(), row[5] = g.y(), row[6] = g.z();
                rows[i] = row;
            }
        });
        Eigen::Matrix<double, 7, 7> JtJ = Eigen::Matrix<double, 7, 7>::Zero();
        Eigen::Matrix<double, 7, 1> Jtr = Eigen::Matrix<double, 7, 1>::Zero();
        for (std::size_t i = 0; i < n; ++i) {
            JtJ += rows[i] * rows[i].transpose() / double(n);
            Jtr += rows[i] * res[i] / double(n);
        }
        if (allow_scale) {  // the scale's residual kScaleWeight * (log s - log s0)
            JtJ(0, 0) += kScaleWeight * kScaleWeight;
            Jtr[0] += kScaleWeight * kScaleWeight * (pose.log_scale - scale0);
        }
        bool improved = false;
        for (int attempt = 0; attempt < 8; ++attempt) {
            Eigen::Matrix<double, 7, 7> A = JtJ;
            for (int k = 0; k < 7; ++k) A(k, k) += lambda * (JtJ(k, k) + 1e-12);
            const Eigen::Matrix<double, 7, 1> step = -A.ldlt().solve(Jtr);
            Pose next = pose;
            next.log_scale += step[0];
            next.rotation = rotation_of(step.segment<3>(1)) * pose.rotation;
            // y = s R x + t: rotating about the current transformed origin keeps t, and the
            // first-order model above assumed exactly that.
            next.translation += step.segment<3>(4);
            const double e = cost(next);
            if (std::isfinite(e) && e < current) {
                pose = next;
                const double gain = current - e;
                current = e;
                lambda = std::max(lambda * 0.3, 1e-9);
                improved = true;
                if (gain < 1e-10 * std::max(current, 1e-20) + 1e-16) return pose;
                break;
            }
            lambda *= 10;
        }
        if (!improved) break;
    }
    return pose;
}

}  // namespace

SimilarityResult compare_to(const PointCloud& sample, const PointCloud& reference_cloud, const RbfField& reference,
                            const SimilarityOptions& options) {
    if (sample.points.size() < 4) throw Error("similarity: the sample needs at least 4 points");
    if (reference_cloud.points.size() < 4) throw Error("similarity: the reference needs at least 4 points");
    std::vector<Vec3d> chosen;
    const std::size_t n = sample.points.size();
    const std::size_t m = std::min(n, std::max<std::size_t>(options.max_points, 16));
    for (std::size_t i = 0; i < m; ++i) chosen.push_back(sample.points[i * n / m]);
    const Frame fa = frame_of(sample.points), fb = frame_of(reference_cloud.points);
    std::vector<Eigen::Vector3d> pts;
    for (const Vec3d& p : chosen) pts.emplace_back(p[0], p[1], p[2]);
    const double size = fb.size;
    // Every proper rotation taking the sample's axes to the reference's axes up to order and
    // sign (24), each scored by the energy of a quarter of the points.
    std::vector<std::pair<double, Pose>> candidates;
    std::vector<Eigen::Vector3d> few;
    for (std::size_t i = 0; i < pts.size(); i += 4) few.push_back(pts[i]);
    const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (const auto& perm : perms)
        for (int signs = 0; signs < 8; ++signs) {
            Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
            for (int k = 0; k < 3; ++k) P(perm[k], k) = (signs >> k & 1) ? -1.0 : 1.0;
            const Eigen::Matrix3d R = fb.axes * P * fa.axes.transpose();
            if (R.determinant() < 0) continue;
            Pose pose;
            pose.log_scale = options.allow_scale ? std::log(fb.size / fa.size) : 0.0;
            pose.rotation = R;
            pose.translation = fb.centroid - std::exp(pose.log_scale) * (R * fa.centroid);
            candidates.emplace_back(energy(reference, few, pose, size), pose);
        }
    std::stable_sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    SimilarityResult best;
    best.energy = std::numeric_limits<double>::infinity();
    const std::size_t tries = std::min<std::size_t>(candidates.size(), 4);
    for (std::size_t c = 0; c < tries; ++c) {
        int used = 0;
        const double coarse = energy(reference, pts, candidates[c].second, size);
        const Pose pose = refine(reference, pts, candidates[c].second, size, options.iterations, options.allow_scale, used);
        const double e = energy(reference, pts, pose, size);
        if (e < best.energy) {
            best.energy = e;
            best.coarse_energy = coarse;
            best.iterations = used;
            best.transform.scale = std::exp(pose.log_scale);
            for (int r = 0; r < 3; ++r)
                for (int k = 0; k < 3; ++k) best.transform.rotation[std::size_t(3 * r + k)] = pose.rotation(r, k);
            for (int r = 0; r < 3; ++r) best.transform.translation[std::size_t(r)] = pose.translation[r];
        }
    }
    return best;
}

SimilarityResult compare_solids(const PointCloud& a, const RbfField& field_a, const PointCloud& b, const RbfField& field_b,
                                const SimilarityOptions& options) {
    SimilarityResult r = compare_to(a, b, field_b, options);
    // The reverse energy: b's points taken onto a by the inverse transform, in a's field.
    const Similarity& t = r.transform;
    const Frame fa = frame_of(a.points);
    const std::size_t n = b.points.size();
    const std::size_t m = std::min(n, std::max<std::size_t>(options.max_points, 16));
    std::vector<Eigen::Vector3d> pts;
    for (std::size_t i = 0; i < m; ++i) pts.emplace_back(b.points[i * n / m][0], b.points[i * n / m][1], b.points[i * n / m][2]);
    Eigen::Matrix3d R;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) R(i, k) = t.rotation[std::size_t(3 * i + k)];
    Pose inverse;
    inverse.log_scale = -std::log(t.scale);
    inverse.rotation = R.transpose();
    inverse.translation = -(1.0 / t.scale) * (R.transpose() * Eigen::Vector3d(t.translation[0], t.translation[1], t.translation[2]));
    r.reverse_energy = energy(field_a, pts, inverse, fa.size);
    r.forward_energy = r.energy;
    r.energy = 0.5 * (r.forward_energy + r.reverse_energy);
    return r;
}

}  // namespace vdbmesh
