// The page's close-ups (GET /api/splats?closeup=N): where a camera is close, the server names
// a box whose full-mesh triangles replace the splats inside it; judged by the box's triangles
// as GET /api/mesh?level=region serves them and by the splats' centres.

#include <gtest/gtest.h>
#include <httplib.h>

#include <cstring>
#include <sstream>
#include <thread>
#include <vector>

#include "phantom_grid.h"
#include "splat_camera.h"
#include "test_data.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/phantom.h"
#include "vdbmesh/view.h"

namespace vdbmesh {
namespace {

/// A cylinder along x across two 128^3 nodes, converted like a scan and read by region from a .vdb.
class CloseUpTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        PhantomSpec spec = phantom_preset("cylinder", {200, 48, 60});
        spec.radius = 17;
        spec.height = 180;
        spec.rotation_degrees = {0, 90, 0};
        grid_ = test::phantom_scan_grid(spec);
        dir_ = new test::ScratchDir;
        write_vdb(*grid_, *dir_ / "cylinder.vdb");
        ViewSource source;
        source.name = "cylinder.vdb";
        source.scan = std::make_shared<const ViewScan>(prepare_grid_regions(open_vdb_regions(*dir_ / "cylinder.vdb")));
        source.initial_iso = 0.5;
        server_ = new ViewServer(source, ViewServerOptions{});
        serving_ = new std::thread([] { server_->run(); });
    }
    static void TearDownTestSuite() {
        server_->stop();
        serving_->join();
        delete serving_;
        delete server_;
        grid_.reset();
        delete dir_;
    }

    static httplib::Result get(const std::string& path) {
        httplib::Client client("127.0.0.1", server_->port());
        client.set_read_timeout(60, 0);
        return client.Get(path.c_str());
    }

    /// GET /api/splats for a camera @a distance voxels above the cylinder's axis (its radius is
    /// 17), looking at its middle along -z, with closeup=@a most.
    static httplib::Result splats(double distance, std::size_t most) {
        const openvdb::Vec3d centre = grid_->transform().indexToWorld(openvdb::Vec3d(100, 24, 30));
        const double voxel = grid_->voxelSize()[0];
        const SplatView camera = test::camera_at({centre.x(), centre.y(), centre.z() + distance * voxel}, centre);
        std::string vp;
        for (double v : camera.view_projection) vp += (vp.empty() ? "" : ",") + std::to_string(v);
        std::ostringstream query;
        query.precision(17);
        query << "/api/splats?vp=" << vp << "&eye=" << camera.eye[0] << "," << camera.eye[1] << "," << camera.eye[2]
              << "&focal=" << camera.focal_pixels << "&closeup=" << most;
        return get(query.str());
    }

    static openvdb::FloatGrid::Ptr grid_;
    static test::ScratchDir* dir_;
    static ViewServer* server_;
    static std::thread* serving_;
};
openvdb::FloatGrid::Ptr CloseUpTest::grid_;
test::ScratchDir* CloseUpTest::dir_ = nullptr;
ViewServer* CloseUpTest::server_ = nullptr;
std::thread* CloseUpTest::serving_ = nullptr;

IndexBox parse_box(const std::string& text) {
    std::istringstream in(text);
    std::array<std::int32_t, 6> v{};
    char comma = 0;
    for (int i = 0; i < 6; ++i) {
        in >> v[i];
        if (i < 5) in >> comma;
    }
    EXPECT_FALSE(in.fail()) << text;
    return IndexBox{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
}

TEST_F(CloseUpTest, FromAfarThereIsNoCloseUp) {
    const auto far = splats(5000, 1'000'000);
    ASSERT_TRUE(far);
    ASSERT_EQ(far->status, 200) << far->body;
    EXPECT_GT(std::stoull(far->get_header_value("X-Splats")), 0u);
    EXPECT_FALSE(far->has_header("X-Closeup-Box"));
}

TEST_F(CloseUpTest, CloseUpTheBoxsTrianglesReplaceTheSplatsInIt) {
    const auto near = splats(40, 1'000'000);
    ASSERT_TRUE(near);
    ASSERT_EQ(near->status, 200) << near->body;
    ASSERT_TRUE(near->has_header("X-Closeup-Box"));
    const IndexBox box = parse_box(near->get_header_value("X-Closeup-Box"));
    for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(box.min[a] % 32, 0) << a;  // snapped, so that small moves ask for the same box
        EXPECT_EQ(box.max[a] % 32, 0) << a;
    }
    EXPECT_LT(box.max[0] - box.min[0], 200);  // a part of the cylinder, not the whole
    // The triangles the page then asks for: some, and no more than the estimate says.
    const std::string box_text = near->get_header_value("X-Closeup-Box");
    const auto mesh = get("/api/mesh?level=region&iso=0.5&box=" + box_text);
    ASSERT_TRUE(mesh);
    ASSERT_EQ(mesh->status, 200) << mesh->body;
    const std::size_t triangles = std::stoull(mesh->get_header_value("X-Triangles"));
    EXPECT_GT(triangles, 100u);
    EXPECT_LE(triangles, std::stoull(near->get_header_value("X-Closeup-Triangles")));
    // The splats whose centres lie in the box come last, and are counted as replaced.
    const std::size_t count = std::stoull(near->get_header_value("X-Splats"));
    const std::size_t inside = std::stoull(near->get_header_value("X-Closeup-Splats"));
    ASSERT_EQ(near->body.size(), 28 * count);
    ASSERT_GT(inside, 0u);
    for (std::size_t i = 0; i < count; ++i) {
        float centre[3];
        std::memcpy(centre, near->body.data() + 28 * i, sizeof centre);
        const openvdb::Vec3d at = grid_->transform().worldToIndex(openvdb::Vec3d(centre[0], centre[1], centre[2]));
        bool in = true;
        for (int a = 0; a < 3; ++a) in = in && at[a] >= box.min[a] && at[a] < box.max[a];
        EXPECT_EQ(in, i >= count - inside) << "splat " << i << " of " << count;
    }
}

TEST_F(CloseUpTest, ACloseUpOverItsTriangleLimitIsNotOffered) {
    const auto near = splats(40, 10);
    ASSERT_TRUE(near);
    ASSERT_EQ(near->status, 200) << near->body;
    EXPECT_FALSE(near->has_header("X-Closeup-Box"));
    const auto bad = splats(40, 0);
    ASSERT_TRUE(bad);
    EXPECT_EQ(bad->status, 400);
    EXPECT_NE(bad->body.find("closeup"), std::string::npos) << bad->body;
}

}  // namespace
}  // namespace vdbmesh
