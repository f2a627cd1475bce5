// Issue 9's dominance figure, without its time column (times belong in bench/): on the bunny
// CT, the CThead and the walnut CT, a DC mesh at one of the issue's --error values has no more
// triangles, no larger two-sided Hausdorff distance to the trilinear isosurface, no larger share
// of angles under 10 degrees and no defect than volumeToMesh at adaptivity 0.1 and 0.25 (the
// CThead: 0.25 only), measured by compare_meshers() in one run. Which DC mesh wins each pair
// is the one bench/README.md names.
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
#include "vdbmesh/compare.h"

namespace vdbmesh {
namespace {

/// volumeToMesh at @a adaptivity, and the DC --error that must beat it on every count.
struct Pair {
    double adaptivity;
    double error;
};

// Measured in session 11 (triangles / Hausdorff voxels / angles under 10 degrees):
//  bunny  a=0.1:  volumeToMesh 708,230 / 1.137 / 1.51%;  DC 0.5: 654,520 / 0.912 / 0.63%
//  bunny  a=0.25: volumeToMesh 602,390 / 1.538 / 1.71%;  DC 1:   558,264 / 1.377 / 0.57%
//  CThead a=0.25: volumeToMesh 264,790 / 1.172 / 2.26%;  DC 1:   250,996 / 1.043 / 0.74%
//  walnut a=0.1:  volumeToMesh 313,900 / 1.006 / 2.41%;  DC 0.5: 250,404 / 0.963 / 0.70%
//  walnut a=0.25: volumeToMesh 263,456 / 1.353 / 2.85%;  DC 0.5
// The CThead pair failed on the Hausdorff distance (DC 1: 1.446) until a polygon that drops an
// edge's crossing had to pass within the error of it (ifc_polygons.cpp, polygon_near()).
// The Hausdorff distances are maxima over 100,000 samples each way, drawn from fixed seeds, so
// the close pair (walnut at 0.1) is decided the same in every run.

/// A scan of the shared data and the pairs it must win.
struct Scan {
    test::SharedScan scan;
    std::vector<Pair> pairs;
};

std::ostream& operator<<(std::ostream& out, const Scan& scan) { return out << scan.scan.name; }

const std::vector<Scan> kScans = {
    {test::shared_scan("BunnyCt"), {{0.1, 0.5}, {0.25, 1.0}}},
    {test::shared_scan("CThead"), {{0.25, 1.0}}},
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

TEST_P(CompareDominanceTest, SomeDcMeshBeatsVolumeToMeshOnEveryCount) {
    const Scan& scan = GetParam();
    openvdb::FloatGrid::Ptr grid;
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan.scan, grid));
    if (!grid) return;  // skipped: the shared data is missing

    CompareOptions options;
    options.iso = scan.scan.iso;
    options.errors.clear();
    options.adaptivities.clear();
    for (const Pair& pair : scan.pairs) {
        options.errors.push_back(pair.error);
        options.adaptivities.push_back(pair.adaptivity);
    }
    options.marching_cubes = false;
    const Comparison comparison = compare_meshers(*grid, options);

    for (const Pair& pair : scan.pairs) {
        const MeshComparison& dc = find(comparison, MeshMethod::dc, pair.error);
        const MeshComparison& vdb = find(comparison, MeshMethod::openvdb, pair.adaptivity);
        std::ostringstream name;
        name << scan.scan.name << ": DC " << pair.error << " against volumeToMesh " << pair.adaptivity;
        const std::string label = name.str();
        std::cout << "[ figures  ] " << label << ": triangles " << dc.analysis.triangles << " / " << vdb.analysis.triangles
                  << ", Hausdorff " << dc.accuracy.distance.hausdorff << " / " << vdb.accuracy.distance.hausdorff
                  << ", angles under 10 degrees " << dc.analysis.small_angle_share << " / " << vdb.analysis.small_angle_share << "\n";
        EXPECT_LE(dc.analysis.triangles, vdb.analysis.triangles) << label;
        EXPECT_LE(dc.accuracy.distance.hausdorff, vdb.accuracy.distance.hausdorff) << label;
        EXPECT_LE(dc.analysis.small_angle_share, vdb.analysis.small_angle_share) << label;
        EXPECT_TRUE(dc.analysis.is_clean()) << label;
    }
}

INSTANTIATE_TEST_SUITE_P(SharedData, CompareDominanceTest, testing::ValuesIn(kScans),
                         [](const testing::TestParamInfo<Scan>& info) { return info.param.scan.name; });

}  // namespace
}  // namespace vdbmesh
