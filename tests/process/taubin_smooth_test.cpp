// taubin_smooth(): smoother (nearer the exact surface) without shrinking, and never
// self-intersecting, on a noisy phantom.

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

#include "process_test_util.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"
#include "vdbmesh/measure.h"
#include "vdbmesh/process.h"

namespace vdbmesh::test {
namespace {

/// The component with the most triangles (the noise adds specks, whose shape smoothing keeps).
Mesh largest_component(const Mesh& mesh) {
    std::vector<Mesh> parts = split_components(mesh);
    return *std::max_element(parts.begin(), parts.end(),
                             [](const Mesh& a, const Mesh& b) { return a.triangles.size() < b.triangles.size(); });
}

// Noise of sigma 0.1 on the 64^3 sphere: 10 lambda/mu pairs make its surface less rough (the
// angle between neighbouring triangles) and keep the volume within 1% (Taubin's point: no
// shrinking, unlike Laplacian smoothing). The noise's long waves (about a voxel high, a few
// voxels long) pass the filter by design, so the distance to the exact sphere drops little.
TEST(TaubinSmoothTest, SmoothsANoisySphereWithoutShrinkingIt) {
    PhantomSpec spec = phantom_preset("sphere", {64, 64, 64});
    spec.noise_sigma = 0.1;
    const Mesh noisy = phantom_mesh(spec);
    const MeshAnalysis before = analyze_mesh(noisy);
    ASSERT_TRUE(before.is_clean());
    TaubinOptions options;
    options.iterations = 10;
    TaubinReport taubin;
    const Mesh smooth = taubin_smooth(noisy, options, &taubin);
    const MeshAnalysis after = analyze_mesh(smooth);
    const double rough_before = rms_dihedral(largest_component(noisy)), rough_after = rms_dihedral(largest_component(smooth));
    std::cout << "roughness " << rough_before << " -> " << rough_after << " rad, distance " << rms_distance(noisy, spec)
              << " -> " << rms_distance(smooth, spec) << ", volume " << before.volume << " -> " << after.volume << ", held back "
              << taubin.held_back << "\n";
    EXPECT_TRUE(after.is_clean());
    EXPECT_EQ(smooth.triangles, noisy.triangles);
    EXPECT_LT(rough_after, 0.9 * rough_before);  // 0.86 -> 0.72 rad measured
    EXPECT_LT(rms_distance(smooth, spec), rms_distance(noisy, spec));
    EXPECT_NEAR(after.volume, before.volume, 0.01 * before.volume);
    // Plain Laplacian smoothing (mu = 0) of the same strength shrinks it measurably.
    options.mu = 0;
    EXPECT_LT(analyze_mesh(taubin_smooth(noisy, options)).volume, 0.99 * before.volume);
}

// Two thin parallel plates of a box-like mesh: a strong lambda would pull them through each
// other; the check puts the offending vertices back, so the result stays clean.
TEST(TaubinSmoothTest, HoldsBackMovesThatWouldIntersect) {
    PhantomSpec spec = phantom_preset("cube-minus-sphere", {48, 48, 48});
    spec.noise_sigma = 0.2;
    const Mesh mesh = phantom_mesh(spec);
    ASSERT_TRUE(analyze_mesh(mesh).is_clean());
    TaubinOptions options;
    options.iterations = 5;
    options.lambda = 1.0;
    options.mu = -1.0;
    const Mesh smooth = taubin_smooth(mesh, options);
    EXPECT_TRUE(analyze_mesh(smooth).is_clean());
}

TEST(TaubinSmoothTest, BadOptionsAreUsageErrors) {
    TaubinOptions options;
    options.iterations = -1;
    EXPECT_THROW(taubin_smooth(Mesh{}, options), UsageError);
}

}  // namespace
}  // namespace vdbmesh::test
