// measure_mesh_stream() (measure --memory, issue 28) against measure_mesh() on the mesh read
// whole: the check's figures, the principal frame and the bounding box bit for bit; each
// component's triangles equal and its area and volume to rounding; a limit too small refused
// with the smallest that works.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "test_data.h"
#include "solids_apart.h"
#include "smallest_limit.h"
#include "test_meshes.h"
#include "vdbmesh/error.h"
#include "vdbmesh/measure.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh {
namespace {

/// Records per sorted run: small enough that the meshes below sort in many runs.
constexpr std::size_t kTinyRuns = 97;

/// A component's area and volume are the same per-triangle terms summed in another order and
/// about another point (the mesh's first corner, not the component's): each term is off by
/// about machine epsilon times the coordinates' magnitude cubed (volume) or squared (area),
/// so the sums agree to 1e-9 of the mesh's whole |volume| and area (the bunny scans below:
/// deviations under 1e-12 of them).
void expect_same_components(const MeshMeasure& whole, const MeshMeasure& stream) {
    ASSERT_EQ(stream.components.size(), whole.components.size());
    const double volume_tolerance = 1e-9 * std::abs(whole.report.volume) + 1e-12, area_tolerance = 1e-9 * whole.report.area;
    // Near-ties in |volume| may fall either way: each component is matched to an equal one.
    std::vector<bool> matched(stream.components.size(), false);
    for (const ComponentMeasure& w : whole.components) {
        bool found = false;
        for (std::size_t i = 0; i < stream.components.size() && !found; ++i) {
            const ComponentMeasure& s = stream.components[i];
            if (matched[i] || s.triangles != w.triangles || std::abs(s.volume - w.volume) > volume_tolerance ||
                std::abs(s.area - w.area) > area_tolerance)
                continue;
            matched[i] = found = true;
        }
        EXPECT_TRUE(found) << "no streamed component like the whole mesh's of " << w.triangles << " triangles, volume " << w.volume;
    }
    // The largest comes first in both unless two are within rounding of each other.
    if (!whole.components.empty()) EXPECT_EQ(stream.components[0].triangles, whole.components[0].triangles);
}

void expect_same_measure(const MeshMeasure& whole, const MeshMeasure& stream) {
    const MeshAnalysis &w = whole.report, &s = stream.report;
    EXPECT_EQ(s.triangles, w.triangles);
    EXPECT_EQ(s.vertices, w.vertices);
    EXPECT_EQ(s.closed, w.closed);
    EXPECT_EQ(s.components, w.components);
    EXPECT_EQ(s.genus, w.genus);
    EXPECT_EQ(s.area, w.area);
    EXPECT_EQ(s.volume, w.volume);
    EXPECT_EQ(s.centroid, w.centroid);
    EXPECT_EQ(s.inertia, w.inertia);
    EXPECT_EQ(stream.principal_moments, whole.principal_moments);
    EXPECT_EQ(stream.principal_axes, whole.principal_axes);
    EXPECT_EQ(stream.box_min, whole.box_min);
    EXPECT_EQ(stream.box_max, whole.box_max);
    expect_same_components(whole, stream);
}

TEST(MeasureStreamTest, EveryFormatGivesTheWholeMeasure) {
    const test::ScratchDir dir;
    for (const std::filesystem::path& file : test::solids_in_every_format(dir.path())) {
        SCOPED_TRACE(file.filename().string());
        const MeshMeasure stream = measure_mesh_stream(file, {test::kPlenty, kTinyRuns});
        expect_same_measure(measure_mesh(read_mesh(file)), stream);
        ASSERT_EQ(stream.components.size(), 3u);
        EXPECT_LT(stream.components[2].volume, 0);  // the cavity
        EXPECT_NEAR(stream.components[2].volume, -1, 1e-12);
    }
}

TEST(MeasureStreamTest, RealScanMeshGivesTheWholeMeasure) {
    // 69451 triangles: the per-triangle sums (16 bytes) outgrow their 1 MiB buffer and go
    // through the temporary file.
    VDBMESH_SHARED_DATA(zipper, "pointcloud_stanford_bunny_scans/reconstruction/bun_zipper.ply");
    expect_same_measure(measure_mesh(read_mesh(zipper)), measure_mesh_stream(zipper, {test::kPlenty, 20000}));
}

TEST(MeasureStreamTest, LimitTooSmallIsRefusedWithTheSmallestThatWorks) {
    const test::ScratchDir dir;
    write_mesh(test::torus(40, 24), dir / "torus.ply");
    const auto measure = [&](std::uint64_t limit) { return measure_mesh_stream(dir / "torus.ply", {limit, 0}); };
    std::string message;
    const std::uint64_t smallest = test::smallest_limit_named(measure, &message);
    EXPECT_NE(message.find("too small to measure"), std::string::npos) << message;
    ASSERT_NE(smallest, 0u);
    EXPECT_EQ(measure(smallest).report.genus, 1);
}

TEST(MeasureStreamTest, TheLeastAnyStreamNeedsTakesAnEmptyStream) {
    const std::uint64_t least = MeshMeasureStream::least_bytes();
    MeshMeasureStream stream("made.ply", {least, 0});
    stream.announced(0, 0);
    EXPECT_EQ(stream.finish().report.triangles, 0u);
    MeshMeasureStream short_of_it("made.ply", {least - 1, 0});
    EXPECT_THROW(short_of_it.announced(1, 0), UsageError);
}

}  // namespace
}  // namespace vdbmesh
