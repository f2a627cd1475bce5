// `vdbmesh measure` run in-process: scikit-image's marching-cubes test ellipsoid measured from
// the volume (isotropic and anisotropic spacing), mesh-file input, and bad input.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <vector>

#include "cli.h"
#include "run_json.h"
#include "test_data.h"
#include "test_meshes.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/write_volume.h"

namespace vdbmesh::test {
namespace {

/// The sample positions of one axis of skimage.draw.ellipsoid(a, b, c, spacing) (scikit-image
/// 0.19): from ceil(-r - s) below floor(r + s + 1) in steps of s, widened to an odd count and
/// shifted so that 0 is a sample.
std::vector<double> skimage_axis(double radius, double spacing) {
    double low = std::ceil(-radius - spacing);
    const double high = std::floor(radius + spacing + 1);
    if (std::fmod(high - low, 2) == 0) low -= 1;
    const auto samples = [&](double first) {
        std::vector<double> x;
        for (std::size_t i = 0; first + double(i) * spacing < high; ++i) x.push_back(first + double(i) * spacing);
        return x;
    };
    double largest_negative = -INFINITY;
    bool has_zero = false;
    for (const double x : samples(low)) {
        has_zero |= x == 0;
        if (x < 0) largest_negative = std::max(largest_negative, x);
    }
    return samples(has_zero ? low : low - largest_negative);
}

/// skimage.draw.ellipsoid(6, 10, 16, spacing, levelset=True) as a float NIfTI with that spacing:
/// (x/6)^2 + (y/10)^2 + (z/16)^2 - 1, negative inside.
std::filesystem::path write_skimage_ellipsoid(const ScratchDir& scratch, const std::array<double, 3>& spacing) {
    const std::array<double, 3> radii{6, 10, 16};
    std::array<std::vector<double>, 3> axes;
    VolumeHeader header;
    header.type = SampleType::f32;
    for (int k = 0; k < 3; ++k) {
        axes[k] = skimage_axis(radii[k], spacing[k]);
        header.dims[k] = std::int64_t(axes[k].size());
    }
    header.spacing = spacing;
    header.index_to_world = axis_aligned_affine(spacing);
    const std::filesystem::path path = scratch / "ellipsoid.nii";
    write_volume(path, header, [&](std::int64_t z, float* slice) {
        for (std::size_t j = 0; j < axes[1].size(); ++j) {
            for (std::size_t i = 0; i < axes[0].size(); ++i) {
                const double x = axes[0][i] / radii[0], y = axes[1][j] / radii[1], w = axes[2][std::size_t(z)] / radii[2];
                *slice++ = float(x * x + y * y + w * w - 1);
            }
        }
    });
    return path;
}

// skimage.draw.ellipsoid_stats(6, 10, 16) (scikit-image 0.19.3, computed once with
// /usr/bin/python3): volume 4021.2385965949347, surface area 1383.282826917989.
constexpr double kEllipsoidVolume = 4021.2385965949347;
constexpr double kEllipsoidArea = 1383.282826917989;

struct EllipsoidCase {
    const char* name;
    std::array<double, 3> spacing;
};

class MeasureEllipsoidTest : public testing::TestWithParam<EllipsoidCase> {};

// Issue 11's figure: within 1% of ellipsoid_stats, with the triangles split in four and the
// vertices on the triquadratic isosurface (--refine; exact for this quadratic field, so what is
// left is the chord error of the flat triangles). Plain Marching Cubes of the quadratic field
// puts every vertex inside: scikit-image's own marching_cubes gives -0.53% area, -1.04% volume
// (isotropic) and -1.16%, -2.09% (anisotropic) on it, and so does the DC mesh at error 0 (Marching Cubes); those
// get 1.2% and 2.2%. On skimage's anisotropic grid (the spacing of its own test) the lower poles
// lie on the first samples: the interpolant's parabolas are shifted inwards there (before they
// were not, the vertices near the poles stayed, and the refined volume was -1.22%). Refined:
// -0.07% area, -0.15% volume (isotropic), -0.17%, -0.35% (anisotropic).
TEST_P(MeasureEllipsoidTest, MatchesSkimageEllipsoidStats) {
    const ScratchDir scratch;
    const auto input = write_skimage_ellipsoid(scratch, GetParam().spacing);
    for (const bool refine : {false, true}) {
        std::vector<std::string> args{"measure", input.string(), "--iso", "0", "--inside", "below", "--json"};
        if (refine) args.push_back("--refine");
        int status = 0;
        const nlohmann::json m = run_json(args, status);
        ASSERT_EQ(status, cli::kSuccess);
        const double area = m["area"], volume = m["volume"];
        std::cout << GetParam().name << (refine ? " refined" : "") << ": area " << area << " (" << 100 * (area / kEllipsoidArea - 1)
                  << "%), volume " << volume << " (" << 100 * (volume / kEllipsoidVolume - 1) << "%)\n";
        EXPECT_NEAR(area, kEllipsoidArea, (refine ? 0.01 : 0.012) * kEllipsoidArea) << refine;
        EXPECT_NEAR(volume, kEllipsoidVolume, (refine ? 0.01 : 0.022) * kEllipsoidVolume) << refine;
        EXPECT_EQ(m["components"].size(), 1u);
        EXPECT_EQ(m["inertia"].size(), 3u);
        EXPECT_EQ(m["principal_moments"].size(), 3u);
    }
}

INSTANTIATE_TEST_SUITE_P(Spacings, MeasureEllipsoidTest,
                         testing::Values(EllipsoidCase{"isotropic", {1, 1, 1}},
                                         EllipsoidCase{"anisotropic", {1, 10 / 6.0, 16 / 6.0}}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(MeasureCliTest, SkimageAxesHaveSkimagesShape) {
    EXPECT_EQ(skimage_axis(6, 1).size(), 15u);
    EXPECT_EQ(skimage_axis(10, 1).size(), 23u);
    EXPECT_EQ(skimage_axis(16, 1).size(), 35u);
    EXPECT_EQ(skimage_axis(10, 10 / 6.0).size(), 14u);
    EXPECT_EQ(skimage_axis(16, 16 / 6.0).size(), 14u);
}

TEST(MeasureCliTest, MeasuresAMeshFile) {
    const ScratchDir scratch;
    write_mesh(cube({0, 0, 0}, 2), scratch / "cube.stl");
    int status = 0;
    const nlohmann::json m = run_json({"measure", (scratch / "cube.stl").string(), "--json"}, status);
    ASSERT_EQ(status, cli::kSuccess);
    EXPECT_DOUBLE_EQ(m["volume"].get<double>(), 8);
    EXPECT_DOUBLE_EQ(m["area"].get<double>(), 24);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(m["centroid"][k].get<double>(), 1, 1e-12);
    EXPECT_NEAR(m["principal_moments"][0].get<double>(), 8 * 4 / 6.0, 1e-12);
    EXPECT_EQ(m["genus"], 0);
    ASSERT_EQ(m["components"].size(), 1u);
    EXPECT_DOUBLE_EQ(m["components"][0]["volume"].get<double>(), 8);
    EXPECT_EQ(cli::run({"measure", (scratch / "cube.stl").string()}), cli::kSuccess);  // the text table
}

TEST(MeasureCliTest, BadInputIsAnError) {
    const ScratchDir scratch;
    EXPECT_EQ(cli::run({"measure", (scratch / "missing.stl").string()}), cli::kRuntimeError);
    EXPECT_EQ(cli::run({"measure", (scratch / "scan.nii").string()}), cli::kUsageError);  // a scan needs --iso
    write_mesh(cube(), scratch / "cube.stl");
    EXPECT_EQ(cli::run({"measure", (scratch / "cube.stl").string(), "--refine"}), cli::kUsageError);
}

}  // namespace
}  // namespace vdbmesh::test
