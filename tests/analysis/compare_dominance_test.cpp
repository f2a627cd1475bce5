// Issue 9's dominance figure, without its time column (times belong in bench/): on the bunny
// CT, the CThead, the engine and the walnut CT, a DC mesh at one of the issue's --error values
// has no more triangles, no larger two-sided Hausdorff distance to the trilinear isosurface, no
// larger share of angles under 10 degrees and no defect than volumeToMesh at adaptivity 0.1 and
// 0.25, measured by compare_meshers() in one run. Which DC mesh wins each pair is the one
// bench/README.md names. The default suite draws 100,000 samples each way on the engine and the
// walnut (15 and 11 s); the bunny's and the CThead's draws (46 and 39 s in a fresh clone's
// suite, its two costliest figure cases) and the 1,000,000 of the figures below on all four run
// with VDBMESH_FULL=1 (nine minutes for the four), and the benchmark keeps the figures with
// times (issue 27). A 128^3 crop was tried first and is no
// test of this: volumeToMesh does not close a surface cut by the crop's faces as DC does (CThead:
// Hausdorff 36.8 voxels against 0.92), and the bunny's centre is a flat cut through bone.
// Before DC crossed a face its face test refuses along the chord of the face's two crossings
// and kept vertices off their cell's faces (session 9), the bunny pair at 0.1 failed on
// angles: DC 0.5 had 1.67% against 1.51%.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "shared_scan.h"
#include "test_data.h"
#include "vdbmesh/compare.h"

namespace vdbmesh {
namespace {

/// volumeToMesh at @a adaptivity, and the DC --error that must beat it on every count.
struct Pair {
    double adaptivity;
    double error;
};

// Measured in session 12 (compare at 1,000,000 samples; triangles / Hausdorff voxels / angles
// under 10 degrees):
//  bunny  a=0.1:  volumeToMesh 708,230 / 1.383 / 1.51%;  DC 0.5: 663,356 / 0.997 / 0.40%
//  bunny  a=0.25: volumeToMesh 602,390 / 1.821 / 1.71%;  DC 1:   583,492 / 1.681 / 0.39%
//  CThead a=0.1:  volumeToMesh 326,436 / 1.500 / 1.86%;  DC 0.5: 290,552 / 1.146 / 0.48%
//  CThead a=0.25: volumeToMesh 264,790 / 1.605 / 2.26%;  DC 1:   250,922 / 1.372 / 0.36%
//  engine a=0.1:  volumeToMesh 140,322 / 0.997 / 0.52%;  DC 0.5: 118,276 / 0.680 / 0.49%
//  engine a=0.25: volumeToMesh  93,456 / 2.256 / 0.72%;  DC 1:    90,726 / 1.158 / 0.45%
//  walnut a=0.1:  volumeToMesh 313,900 / 1.225 / 2.41%;  DC 0.5: 250,090 / 1.043 / 0.43%
//  walnut a=0.25: volumeToMesh 263,456 / 1.378 / 2.85%;  DC 0.5
// The Hausdorff distance is a maximum over samples, so it is drawn from 1,000,000 samples each
// way here, not compare's default 100,000: with 100,000 it moved by up to 0.3 voxel when a
// change elsewhere in the mesh moved the samples (bunny DC 0.5: 0.91 to 1.20 over three
// nearly equal meshes), and volumeToMesh's rose from 0.88 to 1.50 on the CThead at 0.1. The
// samples come from fixed seeds, so every run decides the same.
// The CThead pairs failed on the Hausdorff distance (DC 1: 1.49) until a polygon that drops an
// edge's crossing had to pass within the error of it (dc_polygons.cpp, polygon_near()) and
// the quarter points of a vertex's spokes were tested (dc_octree.cpp, fan_near_surface());
// the engine's on angles (at 0.25, DC 1: 1.05%) until vertices kept wider margins from their
// cells' faces (dc_block.h, ifc_vertex_boxes()), and at 0.1 (DC 0.5: 0.64%) until blocks
// whose surface only clips a face were split (dual_contouring.cpp, split_clipped_blocks()). Every pair at
// adaptivity 1 fails on triangles.
constexpr std::size_t kSamples = 1000000;
/// The default suite's draw: the same fixed seeds, a tenth of the points.
constexpr std::size_t kQuickSamples = 100000;

/// A scan of the shared data, the pairs it must win, and the default suite's draw.
struct Scan {
    test::SharedScan scan;
    std::vector<Pair> pairs;
    /// Points sampled each way by the default suite: a tenth of kSamples, with the same seeds,
    /// except where that draw misses volumeToMesh's farthest point (CThead at 100,000: 0.88
    /// voxels against 1.50 at 1,000,000, under DC's 0.94).
    std::size_t quick_samples = kQuickSamples;
    /// Whether the default suite draws it too, or only VDBMESH_FULL=1: the whole bunny and
    /// CThead are the suite's costliest figure cases, and the engine and the walnut assert the
    /// same dominance by default.
    bool by_default = true;
};

std::ostream& operator<<(std::ostream& out, const Scan& scan) { return out << scan.scan.name; }

const std::vector<Scan> kScans = {
    {test::shared_scan("BunnyCt"), {{0.1, 0.5}, {0.25, 1.0}}, kQuickSamples, false},
    {test::shared_scan("CThead"), {{0.1, 0.5}, {0.25, 1.0}}, 300000, false},
    {test::shared_scan("EngineNifti"), {{0.1, 0.5}, {0.25, 1.0}}},
    {test::shared_scan("WalnutOpenQVis"), {{0.1, 0.5}, {0.25, 0.5}}},
};

class CompareDominanceTest : public testing::TestWithParam<Scan> {
protected:
    tbb::global_control threads_{tbb::global_control::max_allowed_parallelism, 2};
};

const MeshComparison& find(const Comparison& comparison, MeshMethod method, double setting) {
    for (const MeshComparison& m : comparison.meshes) {
        if (m.method != method) continue;
        if ((m.error && *m.error == setting) || (m.adaptivity && *m.adaptivity == setting)) return m;
    }
    throw std::runtime_error("no such mesh in the comparison");
}

/// Prints the figures of @a ours against @a vdb and checks that ours has no more triangles, no
/// larger Hausdorff distance, no larger share of angles under 10 degrees and no defect.
void expect_beats(const MeshComparison& ours, const MeshComparison& vdb, const std::string& label) {
    std::cout << "[ figures  ] " << label << ": triangles " << ours.analysis.triangles << " / " << vdb.analysis.triangles
              << ", Hausdorff " << ours.accuracy.distance.hausdorff << " / " << vdb.accuracy.distance.hausdorff
              << ", angles under 10 degrees " << ours.analysis.small_angle_share << " / " << vdb.analysis.small_angle_share << "\n";
    EXPECT_LE(ours.analysis.triangles, vdb.analysis.triangles) << label;
    EXPECT_LE(ours.accuracy.distance.hausdorff, vdb.accuracy.distance.hausdorff) << label;
    EXPECT_LE(ours.analysis.small_angle_share, vdb.analysis.small_angle_share) << label;
    EXPECT_TRUE(ours.analysis.is_clean()) << label;
}

/// Checks every pair of @a scan on @a grid in one compare_meshers() run drawing @a samples points each way.
void expect_dominance(const openvdb::FloatGrid& grid, const Scan& scan, std::size_t samples) {
    CompareOptions options;
    options.iso = scan.scan.iso;
    options.errors.clear();
    options.adaptivities.clear();
    for (const Pair& pair : scan.pairs) {
        options.errors.push_back(pair.error);
        options.adaptivities.push_back(pair.adaptivity);
    }
    options.marching_cubes = false;
    options.budget_rows = false;  // (DC's meshes at the errors paired here are what this test checks)
    options.accuracy.samples = samples;
    const Comparison comparison = compare_meshers(grid, options);

    for (const Pair& pair : scan.pairs) {
        const MeshComparison& dc = find(comparison, MeshMethod::dc, pair.error);
        const MeshComparison& vdb = find(comparison, MeshMethod::openvdb, pair.adaptivity);
        std::ostringstream name;
        name << scan.scan.name << " (" << samples << " samples): DC " << pair.error << " against volumeToMesh " << pair.adaptivity;
        const std::string label = name.str();
        expect_beats(dc, vdb, label);
        // A sample with no surface point found within the search counts as the search's
        // radius, which is not a measured distance (the bunny's DC 1 had one by a face of the
        // scan box until the search moved isosurface points beyond the box onto it:
        // isosurface_search.cpp, closest_boundary_point()).
        EXPECT_EQ(dc.accuracy.unresolved_samples, 0u) << label;
        EXPECT_EQ(vdb.accuracy.unresolved_samples, 0u) << label;
    }
}

TEST_P(CompareDominanceTest, SomeDcMeshBeatsVolumeToMeshOnEveryCount) {
    const Scan& scan = GetParam();
    if (!scan.by_default) {
        VDBMESH_FULL_ONLY();
    }
    openvdb::FloatGrid::Ptr grid;
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan.scan, grid));
    if (!grid) return;  // skipped: the shared data is missing
    expect_dominance(*grid, scan, scan.quick_samples);
}

TEST_P(CompareDominanceTest, SomeDcMeshBeatsVolumeToMeshOnEveryCountAtAMillionSamples) {
    VDBMESH_FULL_ONLY();
    const Scan& scan = GetParam();
    openvdb::FloatGrid::Ptr grid;
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan.scan, grid));
    if (!grid) return;  // skipped: the shared data is missing
    expect_dominance(*grid, scan, kSamples);
}

// Issue 29's adaptivity-1 pair, without its time column (bench/README.md, "Triangle budget":
// the budget takes 1.4 to 5.2 times volumeToMesh's time there): the triangle budget at
// volumeToMesh's count (`mesh --triangles`) has no more triangles, no larger Hausdorff distance,
// no larger share of angles under 10 degrees and no defect. Measured (100,000 samples; triangles
// / Hausdorff / angles, budget against volumeToMesh): bunny 444,564 / 1.47 / 0.78% against
// 3.78 / 2.10%; CThead 181,774 / 1.36 / 0.91% against 3.07 / 3.15%; engine 45,626 / 2.46 / 0.88%
// against 3.86 / 1.10%; walnut 175,876 / 1.31 / 0.79% against 3.58 / 4.20%.
TEST_P(CompareDominanceTest, TheBudgetBeatsVolumeToMeshAtAdaptivityOne) {
    VDBMESH_FULL_ONLY();
    const Scan& scan = GetParam();
    openvdb::FloatGrid::Ptr grid;
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan.scan, grid));
    if (!grid) return;  // skipped: the shared data is missing
    CompareOptions options;
    options.iso = scan.scan.iso;
    options.errors.clear();
    options.adaptivities = {1};
    options.marching_cubes = false;
    options.accuracy.samples = kQuickSamples;
    const Comparison comparison = compare_meshers(*grid, options);
    ASSERT_EQ(comparison.meshes.size(), 2u);
    const MeshComparison &vdb = comparison.meshes[0], &budget = comparison.meshes[1];
    ASSERT_EQ(budget.budget, std::optional<std::size_t>(vdb.analysis.triangles));
    expect_beats(budget, vdb, scan.scan.name + ": the budget against volumeToMesh 1");
}

INSTANTIATE_TEST_SUITE_P(SharedData, CompareDominanceTest, testing::ValuesIn(kScans),
                         [](const testing::TestParamInfo<Scan>& info) { return info.param.scan.name; });

}  // namespace
}  // namespace vdbmesh
