// section_mesh_stream() (section --memory, issue 28) against section_mesh() on the mesh read
// whole: the same sections bit for bit from PLY and OBJ files (edges named by vertex numbers,
// as in memory), to rounding from STL (edges named by position); an open mesh refused the same
// way; a limit too small refused with the smallest that works.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "test_data.h"
#include "solids_apart.h"
#include "smallest_limit.h"
#include "test_meshes.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/section.h"

namespace vdbmesh {
namespace {


std::vector<Plane> some_planes() {
    return {axis_plane(2, 0.25), axis_plane(2, 0), axis_plane(0, 11.5), axis_plane(1, 0.1), make_plane({1, 2, 3}, 0.7)};
}

void expect_same_sections(const std::vector<Section>& whole, const std::vector<Section>& stream, double tolerance) {
    ASSERT_EQ(stream.size(), whole.size());
    for (std::size_t i = 0; i < whole.size(); ++i) {
        SCOPED_TRACE("plane " + std::to_string(i));
        const Section &w = whole[i], &s = stream[i];
        ASSERT_EQ(s.loops.size(), w.loops.size());
        EXPECT_EQ(s.holes(), w.holes());
        if (tolerance == 0) {
            EXPECT_EQ(s.area, w.area);
            EXPECT_EQ(s.perimeter, w.perimeter);
            EXPECT_EQ(s.centroid, w.centroid);
            EXPECT_EQ(s.second_moments, w.second_moments);
            for (std::size_t l = 0; l < w.loops.size(); ++l) EXPECT_EQ(s.loops[l].points, w.loops[l].points) << l;
        } else {
            EXPECT_NEAR(s.area, w.area, tolerance * std::abs(w.area) + tolerance);
            EXPECT_NEAR(s.perimeter, w.perimeter, tolerance * w.perimeter + tolerance);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.centroid[k], w.centroid[k], tolerance * 10);
            for (std::size_t l = 0; l < w.loops.size(); ++l) EXPECT_EQ(s.loops[l].points.size(), w.loops[l].points.size()) << l;
        }
    }
}

TEST(SectionStreamTest, EveryFormatGivesTheWholeSections) {
    const test::ScratchDir dir;
    for (const std::filesystem::path& file : test::solids_in_every_format(dir.path())) {
        SCOPED_TRACE(file.filename().string());
        const Mesh mesh = read_mesh(file);
        std::vector<Section> whole;
        for (const Plane& plane : some_planes()) whole.push_back(section_mesh(mesh, plane));
        // STL: the crossing points measured from the other end of an edge where its vertex
        // numbers and positions disagree on which is first: one rounding (1e-16 relative) of
        // coordinates under 16, summed over the loops' points: 1e-12 covers it.
        const bool stl = file.extension() == ".stl";
        expect_same_sections(whole, section_mesh_stream(file, some_planes(), test::kPlenty), stl ? 1e-12 : 0);
        EXPECT_EQ(whole[0].holes(), 1u);  // the torus's hole
        EXPECT_EQ(whole[2].holes(), 1u);  // the cavity
    }
}

TEST(SectionStreamTest, RealScanMeshGivesTheWholeSections) {
    VDBMESH_SHARED_DATA(zipper, "pointcloud_stanford_bunny_scans/reconstruction/bun_zipper.ply");
    const Mesh mesh = read_mesh(zipper);
    std::vector<Plane> planes;
    for (double y = 0.06; y < 0.17; y += 0.02) planes.push_back(axis_plane(1, y));
    std::vector<Section> whole;
    for (const Plane& plane : planes) whole.push_back(section_mesh(mesh, plane));
    expect_same_sections(whole, section_mesh_stream(zipper, planes, test::kPlenty), 0);
    EXPECT_GT(whole[0].area, 0);
}

TEST(SectionStreamTest, OpenMeshIsRefusedAsInMemory) {
    const test::ScratchDir dir;
    Mesh mesh = test::box_123();
    mesh.triangles.pop_back();
    write_mesh(mesh, dir / "open.ply");
    std::string whole, stream;
    try {
        section_mesh(read_mesh(dir / "open.ply"), axis_plane(2, 1.5));
    } catch (const Error& e) {
        whole = e.what();
    }
    try {
        section_mesh_stream(dir / "open.ply", {axis_plane(2, 1.5)}, test::kPlenty);
    } catch (const Error& e) {
        stream = e.what();
    }
    EXPECT_FALSE(whole.empty());
    EXPECT_EQ(stream, whole);
    EXPECT_NO_THROW(section_mesh_stream(dir / "open.ply", {axis_plane(0, 0.5)}, test::kPlenty));  // the cut misses the hole
}

TEST(SectionStreamTest, LimitTooSmallIsRefusedWithTheSmallestThatWorks) {
    const test::ScratchDir dir;
    write_mesh(test::torus(40, 24), dir / "torus.ply");
    const auto section = [&](std::uint64_t limit) { return section_mesh_stream(dir / "torus.ply", {axis_plane(2, 0)}, limit); };
    const std::uint64_t smallest = test::smallest_limit_named(section);
    ASSERT_NE(smallest, 0u);
    EXPECT_EQ(section(smallest).at(0).holes(), 1u);
}

}  // namespace
}  // namespace vdbmesh
