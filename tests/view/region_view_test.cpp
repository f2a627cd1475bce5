// `vdbmesh view` of a grid read by region (a .vdb never held whole): what it prepares against
// the grid held whole, and its close-up triangles (level=region) against the whole grid's mesh
// by mesh_grid() (the library's whole run, not the region code).

#include <gtest/gtest.h>
#include <httplib.h>

#include <cstring>
#include <thread>
#include <vector>

#include "phantom_grid.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/phantom.h"
#include "vdbmesh/read.h"
#include "vdbmesh/scan_regions.h"
#include "vdbmesh/write_volume.h"
#include "vdbmesh/view.h"
#include "view/region_mesh.h"

namespace vdbmesh {
namespace {

using Triangle = std::array<std::array<float, 3>, 3>;

/// A cylinder along x through six 128^3 nodes (more than a region reads).
PhantomSpec cylinder_along_x() {
    PhantomSpec spec = phantom_preset("cylinder", {760, 48, 60});
    spec.radius = 17;
    spec.height = 700;
    spec.rotation_degrees = {0, 90, 0};
    return spec;
}

/// The cylinder converted like a scan (isovalue 0.5, with its scan box), and written to a .vdb.
class RegionViewTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        grid_ = test::phantom_scan_grid(cylinder_along_x());
        dir_ = new test::ScratchDir;
        write_vdb(*grid_, *dir_ / "sphere.vdb");
        scan_ = std::make_shared<const ViewScan>(prepare_grid_regions(open_vdb_regions(*dir_ / "sphere.vdb")));
    }
    static void TearDownTestSuite() {
        scan_.reset();
        grid_.reset();
        delete dir_;
    }

    /// The body of GET @a path from a server of the scan read by region.
    static httplib::Result get(const std::string& path, const ViewServerOptions& options = {}) {
        ViewSource source;
        source.name = "sphere.vdb";
        source.scan = scan_;
        source.initial_iso = 0.5;
        ViewServer server(source, options);
        std::thread serving([&server] { server.run(); });
        httplib::Client client("127.0.0.1", server.port());
        client.set_read_timeout(60, 0);
        auto result = client.Get(path.c_str());
        server.stop();
        serving.join();
        return result;
    }

    static openvdb::FloatGrid::Ptr grid_;
    static test::ScratchDir* dir_;
    static std::shared_ptr<const ViewScan> scan_;
};
openvdb::FloatGrid::Ptr RegionViewTest::grid_;
test::ScratchDir* RegionViewTest::dir_ = nullptr;
std::shared_ptr<const ViewScan> RegionViewTest::scan_;

/// The triangles of the mesh buffers of GET /api/mesh (positions, normals, indices), as corners.
std::vector<Triangle> triangles_of_buffers(const std::string& body, std::size_t vertices, std::size_t triangles) {
    EXPECT_EQ(body.size(), 24 * vertices + 12 * triangles);
    std::vector<std::array<float, 3>> positions(vertices);
    std::memcpy(positions.data(), body.data(), 12 * vertices);
    std::vector<std::array<std::uint32_t, 3>> indices(triangles);
    std::memcpy(indices.data(), body.data() + 24 * vertices, 12 * triangles);
    std::vector<Triangle> out;
    for (const auto& t : indices) out.push_back({positions.at(t[0]), positions.at(t[1]), positions.at(t[2])});
    return out;
}

/// The triangles of @a mesh with a corner inside @a box (index space of @a grid), in order.
std::vector<Triangle> triangles_in_box(const Mesh& mesh, const openvdb::FloatGrid& grid, const IndexBox& box) {
    auto inside = [&](const std::array<float, 3>& p) {
        const openvdb::Vec3d i = grid.transform().worldToIndex(openvdb::Vec3d(p[0], p[1], p[2]));
        for (int a = 0; a < 3; ++a)
            if (i[a] < box.min[a] || i[a] >= box.max[a]) return false;
        return true;
    };
    std::vector<Triangle> out;
    for (const auto& t : mesh.triangles) {
        const Triangle corners{mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
        if (inside(corners[0]) || inside(corners[1]) || inside(corners[2])) out.push_back(corners);
    }
    return out;
}

TEST_F(RegionViewTest, ReadByRegionPreparesWhatTheWholeGridDoes) {
    ASSERT_FALSE(scan_->grid);  // never held whole
    ASSERT_EQ(scan_->regions->nodes().size(), 6u);
    const ViewScan whole = prepare_grid(grid_);
    EXPECT_EQ(scan_->histogram.counts, whole.histogram.counts);
    EXPECT_EQ(scan_->histogram.min, whole.histogram.min);
    EXPECT_EQ(scan_->histogram.max, whole.histogram.max);
    EXPECT_EQ(scan_->suggested_iso, whole.suggested_iso);
    ASSERT_EQ(scan_->coarse_factor, whole.coarse_factor);
    ASSERT_GT(whole.coarse_factor, 1);  // the slabs are read in whole coarse layers
    EXPECT_EQ(scan_->coarse->activeVoxelCount(), whole.coarse->activeVoxelCount());
    const auto coarse = scan_->coarse->getConstAccessor();
    std::size_t compared = 0;
    for (auto v = whole.coarse->cbeginValueOn(); v; ++v, ++compared) ASSERT_EQ(coarse.getValue(v.getCoord()), *v) << v.getCoord();
    EXPECT_GT(compared, 1000u);
    EXPECT_EQ(scan_->coarse->transform(), whole.coarse->transform());
}

TEST_F(RegionViewTest, RegionTrianglesAreTheWholeMeshsTrianglesInTheBox) {
    struct Setting {
        const char* query;
        MeshMethod method;
        double error;
    };
    // Across the nodes' face at x = 384; within one node up to its upper face (whose triangles
    // there are partly made by the next node's blocks); from a node's lower face.
    for (const IndexBox& box : {IndexBox{{350, 10, 0}, {400, 40, 60}}, IndexBox{{330, 0, 0}, {384, 48, 60}},
                                IndexBox{{384, 20, 10}, {420, 48, 50}}})
    for (const Setting& setting : {Setting{"method=dc&error=0.25", MeshMethod::dc, 0.25}, Setting{"method=dc&error=0", MeshMethod::dc, 0},
                                   Setting{"method=mc", MeshMethod::mc, 0}}) {
        std::string box_text;
        for (int i = 0; i < 6; ++i) box_text += (i ? "," : "") + std::to_string(i < 3 ? box.min[i] : box.max[i - 3]);
        SCOPED_TRACE(std::string(setting.query) + " box " + box_text);
        const auto result = get(std::string("/api/mesh?level=region&iso=0.5&box=") + box_text + "&" + setting.query);
        ASSERT_TRUE(result);
        ASSERT_EQ(result->status, 200) << result->body;
        const std::vector<Triangle> served = triangles_of_buffers(result->body, std::stoull(result->get_header_value("X-Vertices")),
                                                                   std::stoull(result->get_header_value("X-Triangles")));
        MeshOptions options;
        options.iso = 0.5;
        options.method = setting.method;
        options.error = setting.error;
        const Mesh whole = mesh_grid(*grid_, options).mesh;
        const std::vector<Triangle> expected = triangles_in_box(whole, *grid_, box);
        ASSERT_GT(expected.size(), 100u);
        ASSERT_LT(expected.size(), whole.triangles.size() / 2);  // a part, not the whole
        EXPECT_EQ(served, expected);
    }
}

TEST_F(RegionViewTest, ABoxAwayFromTheGridHasNoTriangles) {
    for (const char* box : {"5000,5000,5000,5100,5100,5100", "0,0,0,20,20,20"}) {  // no node; a node but no surface
        const auto result = get(std::string("/api/mesh?level=region&box=") + box);
        ASSERT_TRUE(result);
        ASSERT_EQ(result->status, 200) << box << ": " << result->body;
        EXPECT_EQ(result->get_header_value("X-Triangles"), "0") << box;
    }
}

TEST_F(RegionViewTest, BadBoxesAreAnsweredWithTheirReason) {
    for (const char* query : {"level=region", "level=region&box=1,2,3", "level=region&box=0,0,0,10,10,0",
                              "level=region&box=0,0,0,10.5,10,10", "level=full&box=0,0,0,10,10,10"}) {
        const auto result = get(std::string("/api/mesh?") + query);
        ASSERT_TRUE(result) << query;
        EXPECT_EQ(result->status, 400) << query;
        EXPECT_NE(result->body.find("box"), std::string::npos) << query << ": " << result->body;
    }
}

TEST_F(RegionViewTest, FullMeshOfAGridReadByRegionIsTheWholeGridsMesh) {
    const auto result = get("/api/mesh?level=full&method=dc&iso=0.5&error=0.25");
    ASSERT_TRUE(result);
    ASSERT_EQ(result->status, 200) << result->body;
    MeshOptions options;
    options.iso = 0.5;
    options.error = 0.25;
    const Mesh whole = mesh_grid(*grid_, options).mesh;
    const std::vector<Triangle> served = triangles_of_buffers(result->body, std::stoull(result->get_header_value("X-Vertices")),
                                                               std::stoull(result->get_header_value("X-Triangles")));
    EXPECT_EQ(served, triangles_in_box(whole, *grid_, IndexBox{{-1000, -1000, -1000}, {1000, 1000, 1000}}));
}

}  // namespace
}  // namespace vdbmesh

namespace vdbmesh {
namespace {

TEST_F(RegionViewTest, AFullMeshOverTheBudgetIsNotMadeButEstimated) {
    ViewServerOptions options;
    options.triangle_budget = 1000;
    MeshOptions mesh_options;
    mesh_options.iso = 0.5;
    const std::size_t actual = mesh_grid(*grid_, mesh_options).mesh.triangles.size();
    ASSERT_GT(actual, options.triangle_budget);
    for (const char* api : {"mesh", "figures", "download"}) {
        const auto result = get(std::string("/api/") + api + "?level=full&method=dc&iso=0.5&max_triangles=1000", options);
        ASSERT_TRUE(result) << api;
        EXPECT_EQ(result->status, 413) << api;
        EXPECT_EQ(result->get_header_value("X-Estimated"), "1") << api;
        EXPECT_NE(result->body.find("budget"), std::string::npos) << api << ": " << result->body;
        // The coarse surface is smoother than the full one: within a factor of two of the count.
        const double estimate = std::stod(result->get_header_value("X-Triangles"));
        EXPECT_GT(estimate, 0.5 * double(actual)) << api;
        EXPECT_LT(estimate, 2.0 * double(actual)) << api;
    }
    // Close-ups are still served.
    EXPECT_EQ(get("/api/mesh?level=region&box=350,10,0,400,40,60", options)->status, 200);
}

}  // namespace
}  // namespace vdbmesh

namespace vdbmesh {
namespace {

TEST_F(RegionViewTest, ABoxReadingMoreThanAllowedIsRefusedBeforeReading) {
    const IndexBox box{{350, 10, 0}, {400, 40, 60}};
    // The region the box reads: its nodes (x 256, y 0, z 0), one below and two above, and 16 voxels round.
    const std::uint64_t bytes = scan_->regions->estimated_bytes(IndexBox{{112, -144, -144}, {784, 400, 400}});
    ASSERT_GT(bytes, 1000u);
    MeshOptions options;
    options.iso = 0.5;
    EXPECT_GT(view::region_mesh(*scan_->regions, box, options, bytes).triangles.size(), 100u);  // exactly its read: allowed
    try {
        view::region_mesh(*scan_->regions, box, options, bytes - 1);
        FAIL() << "expected a UsageError";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("box"), std::string::npos) << e.what();
    }
}

/// `view SCAN --memory`: the scan itself read by region (surveyed, its rows kept) prepares and
/// meshes a close-up as the .vdb read by region does (open_scan_regions, not the conversion).
TEST_F(RegionViewTest, AScanReadByRegionGivesWhatItsVdbGives) {
    const PhantomSpec spec = cylinder_along_x();
    VolumeHeader header;
    header.dims = spec.dims;
    header.type = SampleType::f32;
    write_volume(*dir_ / "cylinder.nii", header, [&](std::int64_t z, float* slice) { fill_phantom_slice(spec, z, slice); });
    ConvertOptions convert;
    convert.iso = 0.5;
    const std::shared_ptr<const GridRegionSource> scan =
        open_scan_regions([] { return std::unique_ptr<SliceReader>(open_volume(*dir_ / "cylinder.nii")); }, convert);
    const ViewScan prepared = prepare_grid_regions(scan);
    EXPECT_EQ(prepared.histogram.counts, scan_->histogram.counts);
    EXPECT_EQ(prepared.suggested_iso, scan_->suggested_iso);
    EXPECT_EQ(prepared.coarse->activeVoxelCount(), scan_->coarse->activeVoxelCount());
    MeshOptions options;
    options.iso = 0.5;
    options.error = 0.25;
    const IndexBox box{{350, 10, 0}, {400, 40, 60}};
    const Mesh from_scan = view::region_mesh(*scan, box, options, std::uint64_t(1) << 30);
    const Mesh from_vdb = view::region_mesh(*scan_->regions, box, options, std::uint64_t(1) << 30);
    ASSERT_GT(from_vdb.triangles.size(), 100u);
    EXPECT_EQ(from_scan.triangles, from_vdb.triangles);
    EXPECT_EQ(from_scan.vertices, from_vdb.vertices);
}

}  // namespace
}  // namespace vdbmesh
