#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <random>

#include "point_shapes.h"
#include "vdbmesh/points.h"

namespace vdbmesh {
namespace {

struct Copy {
    PointCloud cloud;
    Eigen::Matrix3d rotation;
    double scale;
};

/// A rotated, scaled, translated copy with noise of 1% of the size and 20% of points dropped.
Copy transformed_copy(const PointCloud& c, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Eigen::Vector3d axis(g(rng), g(rng), g(rng));
    axis.normalize();
    Copy out;
    out.rotation = Eigen::AngleAxisd(u(rng) * 2 * M_PI, axis).toRotationMatrix();
    out.scale = 0.5 + 1.5 * u(rng);
    const Eigen::Vector3d t(10 * g(rng), 10 * g(rng), 10 * g(rng));
    const double noise = 0.01 * 2.0 * out.scale;  // the shapes are about 2 across
    for (const Vec3d& p : c.points) {
        if (u(rng) < 0.2) continue;
        const Eigen::Vector3d y = out.scale * (out.rotation * Eigen::Vector3d(p[0], p[1], p[2])) + t +
                                  noise * Eigen::Vector3d(g(rng), g(rng), g(rng));
        out.cloud.points.push_back({y.x(), y.y(), y.z()});
    }
    return out;
}

/// The cube minus a sphere, stretched to 1 x 1.4 x 1.9 so that it has no symmetry.
PointCloud asymmetric_shape(std::size_t count, std::uint64_t seed) {
    PointCloud c = test::sample_shape("cube_minus_sphere", count, seed);
    const double s[3] = {1.0, 1.4, 1.9};
    for (std::size_t i = 0; i < c.points.size(); ++i) {
        double len = 0;
        for (int a = 0; a < 3; ++a) {
            c.points[i][a] *= s[a];
            c.normals[i][a] /= s[a];
            len += c.normals[i][a] * c.normals[i][a];
        }
        for (double& x : c.normals[i]) x /= std::sqrt(len);
    }
    return c;
}

TEST(Similarity, RecoversAKnownRotationAndScale) {
    const PointCloud ref = asymmetric_shape(6000, 21);
    const RbfField field(ref);
    SimilarityOptions o;
    o.max_points = 800;
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
        const Copy copy = transformed_copy(asymmetric_shape(4000, 100 + seed), seed);
        const SimilarityResult r = compare_to(copy.cloud, ref, field, o);
        Eigen::Matrix3d R;
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) R(i, k) = r.transform.rotation[std::size_t(3 * i + k)];
        // The fit maps the copy back: its rotation is the inverse of the known one.
        const double angle = Eigen::AngleAxisd(R * copy.rotation).angle() * 180 / M_PI;
        EXPECT_LT(angle, 2.0) << "seed " << seed;
        EXPECT_NEAR(r.transform.scale * copy.scale, 1.0, 0.01) << "seed " << seed;
    }
}

TEST(Classify, PhantomShapesFromTransformedNoisyPartialCopies) {
    const std::vector<std::string> shapes = {"sphere", "cube", "cylinder", "torus", "cube_minus_sphere"};
    std::vector<PointCloud> refs;
    std::vector<std::unique_ptr<RbfField>> fields;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
        refs.push_back(test::sample_shape(shapes[i], 4000, 31 + i));
        fields.push_back(std::make_unique<RbfField>(refs.back()));
    }
    SimilarityOptions o;
    o.max_points = 500;
    o.iterations = 30;
    for (std::size_t truth = 0; truth < shapes.size(); ++truth) {
        for (std::uint64_t trial = 0; trial < 2; ++trial) {
            const Copy copy = transformed_copy(test::sample_shape(shapes[truth], 3000, 1000 + 10 * truth + trial), 77 + 13 * truth + trial);
            PointCloud sample = copy.cloud;
            estimate_normals(sample);
            const RbfField sample_field(sample);
            std::size_t best = 0;
            double best_energy = 1e300;
            std::string energies;
            for (std::size_t k = 0; k < shapes.size(); ++k) {
                const double e = compare_solids(sample, sample_field, refs[k], *fields[k], o).energy;
                energies += shapes[k] + "=" + std::to_string(e) + " ";
                if (e < best_energy) best_energy = e, best = k;
            }
            EXPECT_EQ(shapes[best], shapes[truth]) << "trial " << trial << ": " << energies;
        }
    }
}

}  // namespace
}  // namespace vdbmesh
