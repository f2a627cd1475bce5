// Issue 3, point 6, on the phantoms: at every --error, the Dual Marching Cubes mesh of every
// phantom shape (the presets of `vdbmesh phantom`: table 3.1 of the coursework, the torus and
// the rotated cube), clean and with noise, is clean as `vdbmesh check` judges it (closed,
// manifold, oriented outward, no degenerate faces, no self-intersecting pairs), and so is the
// Marching Cubes mesh. The phantoms are converted like scans (tests/common/phantom_grid.h).

#include <gtest/gtest.h>

#include <string>

#include "phantom_grid.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/phantom.h"

namespace vdbmesh {
namespace {

constexpr std::int64_t kDim = 96;
/// Density noise (of the 0..1 ramp, 0.1 per voxel): +-0.2 voxel, like a scan's.
constexpr double kNoise = 0.02;

struct PhantomCase {
    std::string preset;
    bool noisy;
};

std::vector<PhantomCase> all_cases() {
    std::vector<PhantomCase> cases;
    for (const std::string& name : phantom_preset_names()) {
        cases.push_back({name, false});
        cases.push_back({name, true});
    }
    return cases;
}

class PhantomGuaranteesTest : public ::testing::TestWithParam<PhantomCase> {};

TEST_P(PhantomGuaranteesTest, EveryErrorGivesACleanMesh) {
    PhantomSpec spec = phantom_preset(GetParam().preset, {kDim, kDim, kDim});
    if (GetParam().noisy) spec.noise_sigma = kNoise;
    const openvdb::FloatGrid::Ptr grid = test::phantom_scan_grid(spec);
    MeshOptions options;
    options.iso = 0.5;
    options.method = MeshMethod::mc;
    EXPECT_TRUE(analyze_mesh(mesh_grid(*grid, options).mesh).is_clean()) << "mc";
    options.method = MeshMethod::dmc;
    for (double error : {0.0, 0.1, 0.25, 0.5, 1.0}) {
        options.error = error;
        const MeshAnalysis report = analyze_mesh(mesh_grid(*grid, options).mesh);
        EXPECT_TRUE(report.is_clean()) << "dmc --error " << error << ": " << report.triangles << " triangles, "
                                       << report.self_intersecting_pairs << " self-intersecting pairs, "
                                       << report.boundary_edges << " boundary edges, " << report.nonmanifold_edges
                                       << " non-manifold edges";
    }
}

INSTANTIATE_TEST_SUITE_P(Phantoms, PhantomGuaranteesTest, ::testing::ValuesIn(all_cases()),
                         [](const ::testing::TestParamInfo<PhantomCase>& info) {
                             std::string name = info.param.preset + (info.param.noisy ? "_noisy" : "");
                             for (char& c : name) {
                                 if (c == '-') c = '_';
                             }
                             return name;
                         });

}  // namespace
}  // namespace vdbmesh
