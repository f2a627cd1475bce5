// The server of `vdbmesh view`, in-process on a free port: its page, its JSON, its mesh
// buffers against the library's own meshes, and its answers to bad requests.

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>
#include <atomic>
#include <chrono>
#include <cstring>
#include <future>
#include <numeric>
#include <optional>
#include <thread>

#include "cli.h"
#include "report_json.h"
#include "splat_camera.h"
#include "test_data.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/phantom.h"
#include "vdbmesh/splats.h"
#include "vdbmesh/view.h"
#include "vdbmesh/write_volume.h"
#include "view/coarse_grid.h"

namespace vdbmesh {
namespace {

constexpr std::int64_t kSize = 40;

/// A blurred sphere phantom (density 1 inside, 0 outside) as a prepared scan.
std::shared_ptr<const ViewScan> phantom_scan() {
    const test::ScratchDir dir;
    const PhantomSpec spec = phantom_preset("sphere", {kSize, kSize, kSize});
    VolumeHeader header;
    header.dims = spec.dims;
    header.type = SampleType::f32;
    write_volume(dir / "sphere.nii", header, [&](std::int64_t z, float* slice) { fill_phantom_slice(spec, z, slice); });
    return std::make_shared<const ViewScan>(prepare_scan([&] { return open_volume(dir / "sphere.nii"); }));
}

/// The triangles of the library's Marching Cubes mesh of @a grid at @a iso.
std::size_t mc_triangle_count(const openvdb::FloatGrid& grid, double iso) {
    MeshOptions options;
    options.method = MeshMethod::mc;
    options.iso = iso;
    return mesh_grid(grid, options).mesh.triangles.size();
}

/// A server on a free port of 127.0.0.1, serving in a thread, and a client for it.
class RunningServer {
public:
    explicit RunningServer(ViewSource source, ViewServerOptions options = {})
        : server_(std::move(source), with_figures(std::move(options))), client_("127.0.0.1", server_.port()),
          thread_([this] { server_.run(); }) {
        client_.set_read_timeout(60, 0);
    }
    ~RunningServer() {
        server_.stop();
        thread_.join();
    }
    httplib::Result get(const std::string& path) { return client_.Get(path.c_str()); }
    int port() const { return server_.port(); }

private:
    static ViewServerOptions with_figures(ViewServerOptions options) {
        options.mesh_figures = [](const Mesh& mesh) { return cli::report_json(analyze_mesh(mesh)).dump(); };
        return options;
    }
    ViewServer server_;
    httplib::Client client_;
    std::thread thread_;
};

class ViewServerTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() { scan_ = phantom_scan(); }
    static void TearDownTestSuite() { scan_.reset(); }

    static ViewSource scan_source() {
        ViewSource source;
        source.name = "sphere.nii";
        source.scan = scan_;
        source.initial_iso = 0.5;
        return source;
    }

    static std::size_t header_count(const httplib::Result& result, const char* name) {
        return std::stoull(result->get_header_value(name));
    }

    static std::shared_ptr<const ViewScan> scan_;
};
std::shared_ptr<const ViewScan> ViewServerTest::scan_;

TEST_F(ViewServerTest, HistogramCountsEverySampleOverTheValueRange) {
    const ValueHistogram& histogram = scan_->histogram;
    EXPECT_EQ(histogram.counts.size(), kViewHistogramBins);
    EXPECT_EQ(std::accumulate(histogram.counts.begin(), histogram.counts.end(), std::uint64_t(0)),
              std::uint64_t(kSize * kSize * kSize));
    EXPECT_NEAR(histogram.min, 0.0, 1e-6);
    EXPECT_NEAR(histogram.max, 1.0, 1e-6);
    EXPECT_GT(scan_->suggested_iso, 0.1);
    EXPECT_LT(scan_->suggested_iso, 0.9);
    EXPECT_EQ(scan_->coarse_factor, 1);  // 40^3 fits the coarse budget
}

TEST_F(ViewServerTest, ServesThePageAndItsScript) {
    RunningServer server(scan_source());
    const auto page = server.get("/");
    ASSERT_TRUE(page);
    EXPECT_EQ(page->status, 200);
    EXPECT_NE(page->body.find("/app.js"), std::string::npos);
    const auto script = server.get("/app.js");
    ASSERT_TRUE(script);
    EXPECT_EQ(script->status, 200);
    EXPECT_GT(script->body.size(), 100000u);  // three.js is in it
    // Sent as it is to a browser accepting compression (compressing it took seconds, issue 30).
    httplib::Client browser("127.0.0.1", server.port());
    browser.set_decompress(false);
    const auto plain = browser.Get("/app.js", {{"Accept-Encoding", "gzip, deflate, br"}});
    ASSERT_TRUE(plain);
    EXPECT_FALSE(plain->has_header("Content-Encoding")) << plain->get_header_value("Content-Encoding");
    EXPECT_TRUE(plain->body == script->body) << plain->body.size() << " bytes, not the script's " << script->body.size();
    EXPECT_EQ(server.get("/missing")->status, 404);
}

TEST_F(ViewServerTest, InfoDescribesTheScan) {
    RunningServer server(scan_source(), ViewServerOptions{"127.0.0.1", 0, 1234, {}});
    const auto result = server.get("/api/info");
    ASSERT_TRUE(result);
    const auto info = nlohmann::json::parse(result->body);
    EXPECT_EQ(info["kind"], "scan");
    EXPECT_EQ(info["name"], "sphere.nii");
    EXPECT_EQ(info["triangle_budget"], 1234);
    EXPECT_EQ(info["scan"]["histogram"].size(), kViewHistogramBins);
    EXPECT_DOUBLE_EQ(info["scan"]["initial_iso"].get<double>(), 0.5);
    EXPECT_DOUBLE_EQ(info["scan"]["suggested_iso"].get<double>(), scan_->suggested_iso);
}

TEST_F(ViewServerTest, MeshBuffersAreTheLibrarysMesh) {
    RunningServer server(scan_source());
    const auto result = server.get("/api/mesh?level=full&method=dc&iso=0.5&error=0.25");
    ASSERT_TRUE(result);
    ASSERT_EQ(result->status, 200);
    MeshOptions options;
    options.iso = 0.5;
    options.error = 0.25;
    const Mesh expected = mesh_grid(*scan_->grid, options).mesh;
    const std::size_t vertices = header_count(result, "X-Vertices"), triangles = header_count(result, "X-Triangles");
    EXPECT_EQ(vertices, expected.vertices.size());
    EXPECT_EQ(triangles, expected.triangles.size());
    ASSERT_EQ(result->body.size(), 24 * vertices + 12 * triangles);
    std::array<float, 3> first_position;
    std::memcpy(first_position.data(), result->body.data(), sizeof first_position);
    EXPECT_EQ(first_position, expected.vertices.front());
    std::array<std::uint32_t, 3> last_triangle;
    std::memcpy(last_triangle.data(), result->body.data() + result->body.size() - 12, 12);
    EXPECT_EQ(last_triangle, expected.triangles.back());
}

TEST_F(ViewServerTest, IsovalueAndLevelChangeTheMesh) {
    RunningServer server(scan_source());
    const auto low = server.get("/api/mesh?level=full&method=mc&iso=0.3");
    const auto high = server.get("/api/mesh?level=full&method=mc&iso=0.7");
    ASSERT_TRUE(low && high);
    EXPECT_GT(header_count(low, "X-Triangles"), header_count(high, "X-Triangles"));  // a larger sphere
    const auto default_iso = server.get("/api/mesh?method=mc");
    const auto at_half = server.get("/api/mesh?method=mc&iso=0.5");
    EXPECT_EQ(default_iso->body, at_half->body);
}

/// The box around a mesh's vertices.
openvdb::BBoxd bounds(const Mesh& mesh) {
    openvdb::BBoxd box;
    for (const auto& v : mesh.vertices) box.expand(openvdb::Vec3d(v[0], v[1], v[2]));
    return box;
}

TEST_F(ViewServerTest, CoarseGridMeshesTheSameSphereInTheSamePlace) {
    const openvdb::CoordBBox box = stored_scan_box(*scan_->grid).value();
    const auto coarse = view::coarse_grid(*scan_->grid, box, 2);
    MeshOptions options;
    options.method = MeshMethod::mc;
    options.iso = 0.5;
    const openvdb::BBoxd full_box = bounds(mesh_grid(*scan_->grid, options).mesh);
    const openvdb::BBoxd coarse_box = bounds(mesh_grid(*coarse, options).mesh);
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_NEAR(coarse_box.getCenter()[axis], full_box.getCenter()[axis], 0.5);
        EXPECT_NEAR(coarse_box.extents()[axis], full_box.extents()[axis], 2.0);
    }
}

TEST(CoarseFactorTest, TheBunnyCtIsAveragedOverBlocksOfFour) {
    const openvdb::CoordBBox bunny(openvdb::Coord(0), openvdb::Coord(511, 511, 360));
    EXPECT_EQ(view::coarse_factor(bunny, kCoarseSampleBudget), 4);  // 128 x 128 x 91 samples
    EXPECT_EQ(view::coarse_factor(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(9)), kCoarseSampleBudget), 1);
}

TEST_F(ViewServerTest, CoarseLevelMeshesTheCoarseGrid) {
    RunningServer server(scan_source());
    const auto coarse = server.get("/api/mesh?level=coarse&iso=0.5");
    ASSERT_TRUE(coarse);
    EXPECT_EQ(coarse->status, 200);
    EXPECT_EQ(header_count(coarse, "X-Triangles"), mc_triangle_count(*scan_->coarse, 0.5));
}

/// A stand-in for the mesher that holds the first full mesh asked of it inside, reporting
/// progress as mesh_grid() does between its steps, until the store gives it up (progress
/// throws); it meshes everything else as mesh_grid(). No sleeps: the held request leaves
/// the mesher only when superseded, so the test's order of events is fixed.
class HeldFullMesher {
public:
    GridMesher mesher() {
        return [this](const openvdb::FloatGrid& grid, const MeshOptions& options) { return mesh(grid, options); };
    }
    /// Returns once the held request is inside the mesher (holding the store).
    void wait_until_held() { held_future_.wait(); }

private:
    MeshResult mesh(const openvdb::FloatGrid& grid, const MeshOptions& options) {
        if (options.progress && !holding_.exchange(true)) {
            held_.set_value();
            // A store that never gives up fails the test instead of hanging it: within the
            // client's read timeout (60 s), the held mesh is made after all.
            const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
            while (std::chrono::steady_clock::now() < deadline) {
                options.progress(0.5);
                std::this_thread::yield();
            }
        }
        return mesh_grid(grid, options);
    }

    std::atomic<bool> holding_{false};
    std::promise<void> held_;
    std::shared_future<void> held_future_ = held_.get_future().share();
};

TEST_F(ViewServerTest, ANewSettingGivesUpTheFullMeshInFlightWith409) {
    HeldFullMesher held;
    ViewServerOptions options;
    options.mesher = held.mesher();
    RunningServer server(scan_source(), options);
    constexpr const char* kOlderFull = "/api/mesh?level=full&method=mc&iso=0.5";
    std::optional<httplib::Result> older;
    std::thread older_page([&] {  // the page before the slider moved: its full mesh
        httplib::Client client("127.0.0.1", server.port());
        client.set_read_timeout(60, 0);
        older.emplace(client.Get(kOlderFull));
    });
    held.wait_until_held();
    // The slider released: the page asks for the coarse mesh of the new isovalue first.
    const auto newer = server.get("/api/mesh?level=coarse&iso=0.6");
    older_page.join();

    ASSERT_TRUE(older && *older && newer);
    ASSERT_EQ((*older)->status, 409);
    EXPECT_NE(nlohmann::json::parse((*older)->body)["error"].get<std::string>().find("superseded"), std::string::npos);
    EXPECT_EQ(newer->status, 200);
    EXPECT_EQ(header_count(newer, "X-Triangles"), mc_triangle_count(*scan_->coarse, 0.6));

    // Given up, not kept: asked for again, the older full mesh is made in full.
    const auto again = server.get(kOlderFull);
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 200);
    EXPECT_EQ(header_count(again, "X-Triangles"), mc_triangle_count(*scan_->grid, 0.5));
}

TEST_F(ViewServerTest, FiguresAreThoseOfCheck) {
    RunningServer server(scan_source());
    const auto result = server.get("/api/figures?level=full&iso=0.5");
    ASSERT_TRUE(result);
    ASSERT_EQ(result->status, 200);
    const auto figures = nlohmann::json::parse(result->body);
    EXPECT_TRUE(figures["check"]["closed"].get<bool>());
    EXPECT_EQ(figures["check"]["self_intersecting_pairs"], 0);
    EXPECT_EQ(figures["check"]["triangles"], figures["triangles"]);
    EXPECT_GT(figures["check"]["volume"].get<double>(), 0.0);
    EXPECT_GE(figures["seconds"].get<double>(), 0.0);
}

TEST_F(ViewServerTest, DownloadsTheMeshAsStlPlyAndObj) {
    RunningServer server(scan_source());
    const auto mesh = server.get("/api/mesh?iso=0.5");
    const std::size_t triangles = header_count(mesh, "X-Triangles");
    const auto stl = server.get("/api/download?format=stl&iso=0.5");
    ASSERT_TRUE(stl);
    EXPECT_EQ(stl->body.size(), 84 + 50 * triangles);
    EXPECT_EQ(server.get("/api/download?format=ply&iso=0.5")->body.rfind("ply\n", 0), 0u);
    EXPECT_EQ(server.get("/api/download?format=obj&iso=0.5")->status, 200);
    EXPECT_EQ(server.get("/api/download?format=gltf&iso=0.5")->status, 400);
}

TEST_F(ViewServerTest, BadRequestsAreAnsweredWithTheirReason) {
    RunningServer server(scan_source());
    const auto method = server.get("/api/mesh?method=voxels");
    EXPECT_EQ(method->status, 400);
    EXPECT_NE(nlohmann::json::parse(method->body)["error"].get<std::string>().find("method"), std::string::npos);
    EXPECT_EQ(server.get("/api/mesh?iso=abc")->status, 400);
    EXPECT_EQ(server.get("/api/mesh?level=medium")->status, 400);
    EXPECT_EQ(server.get("/api/mesh?error=-1")->status, 400);
    EXPECT_EQ(server.get("/api/mesh?method=openvdb&adaptivity=2")->status, 400);
    const auto over = server.get("/api/mesh?iso=0.5&max_triangles=10");
    EXPECT_EQ(over->status, 413);
    EXPECT_GT(header_count(over, "X-Triangles"), 10u);
}

/// The query of GET /api/splats for @a camera.
std::string splat_query(const SplatView& camera) {
    std::string vp;
    for (double v : camera.view_projection) vp += (vp.empty() ? "" : ",") + std::to_string(v);
    return "/api/splats?vp=" + vp + "&eye=" + std::to_string(camera.eye[0]) + "," + std::to_string(camera.eye[1]) + "," +
           std::to_string(camera.eye[2]) + "&focal=" + std::to_string(camera.focal_pixels);
}

TEST_F(ViewServerTest, SplatsAreTheLibrarysSelectionOfTheScansTree) {
    RunningServer server(scan_source());
    const openvdb::Vec3d centre = scan_->grid->transform().indexToWorld(openvdb::Vec3d(kSize / 2.0));
    std::size_t far_count = 0;
    int far_level = 0;
    for (double distance : {10000.0, 60.0}) {
        const SplatView camera = test::camera_at({centre.x(), centre.y(), centre.z() + distance}, centre);
        const auto response = server.get(splat_query(camera));
        ASSERT_TRUE(response);
        ASSERT_EQ(response->status, 200) << response->body;
        // The library's tree of the full grid at the initial isovalue, and its selection.
        SplatOptions options;
        options.iso = scan_source().initial_iso;
        const SplatTree tree = build_splat_tree(*scan_->grid, options);
        const SplatSelection expected = select_splats(tree, camera);
        ASSERT_FALSE(expected.nodes.empty());
        EXPECT_EQ(response->get_header_value("X-Splats"), std::to_string(expected.nodes.size()));
        EXPECT_EQ(response->get_header_value("X-Level"), std::to_string(expected.finest_level));
        EXPECT_EQ(response->get_header_value("X-Cut-Level"), std::to_string(expected.cut_level));
        EXPECT_EQ(response->get_header_value("X-Tree-Nodes"), std::to_string(tree.nodes.size()));
        ASSERT_EQ(response->body.size(), 28 * expected.nodes.size());
        float first[7];
        std::memcpy(first, response->body.data(), sizeof first);
        EXPECT_EQ(first[0], tree.nodes[expected.nodes[0]].centre[0]);
        EXPECT_EQ(first[6], tree.nodes[expected.nodes[0]].radius);
        if (distance > 1000) {
            far_count = expected.nodes.size();
            far_level = expected.finest_level;
        } else {
            EXPECT_GT(expected.nodes.size(), far_count);  // closer: finer
            EXPECT_LT(expected.finest_level, far_level);
        }
    }
}

TEST_F(ViewServerTest, BadSplatRequestsNameTheParameter) {
    RunningServer server(scan_source());
    const auto missing = server.get("/api/splats?eye=0,0,1");
    ASSERT_TRUE(missing);
    EXPECT_EQ(missing->status, 400);
    EXPECT_NE(missing->body.find("vp: expected 16 comma-separated numbers"), std::string::npos) << missing->body;
    const std::string vp = "1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1";
    const auto short_eye = server.get("/api/splats?vp=" + vp + "&eye=0,1");
    ASSERT_TRUE(short_eye);
    EXPECT_EQ(short_eye->status, 400);
    EXPECT_NE(short_eye->body.find("eye: expected 3"), std::string::npos) << short_eye->body;
    const auto bad_budget = server.get("/api/splats?vp=" + vp + "&eye=0,0,1&budget=-4");
    ASSERT_TRUE(bad_budget);
    EXPECT_EQ(bad_budget->status, 400);
    EXPECT_NE(bad_budget->body.find("budget: expected a number > 0"), std::string::npos) << bad_budget->body;
}

TEST_F(ViewServerTest, MeshFilesAreServedAsTheyAre) {
    MeshOptions options;
    options.iso = 0.5;
    ViewSource source;
    source.name = "sphere.stl";
    source.mesh = std::make_shared<const Mesh>(mesh_grid(*scan_->grid, options).mesh);
    RunningServer server(source);
    EXPECT_EQ(nlohmann::json::parse(server.get("/api/info")->body)["kind"], "mesh");
    const auto result = server.get("/api/mesh?iso=0.9");  // the isovalue means nothing here
    ASSERT_TRUE(result);
    EXPECT_EQ(header_count(result, "X-Triangles"), source.mesh->triangles.size());
}

TEST_F(ViewServerTest, APortInUseIsAnError) {
    RunningServer first(scan_source());
    ViewServerOptions options;
    options.port = first.port();
    EXPECT_THROW(ViewServer(scan_source(), options), Error);
}

TEST_F(ViewServerTest, ThePageIsServedWhileTheSourceIsMadeAndTheApiWaitsForIt) {
    std::promise<void> release;
    ViewServer server([held = release.get_future().share()] {
        held.wait();  // the source's reading, held until the page has been asked for
        return scan_source();
    }, ViewServerOptions{});
    std::thread serving([&] { server.run(); });
    httplib::Client client("127.0.0.1", server.port());
    EXPECT_EQ(client.Get("/")->status, 200);
    EXPECT_EQ(client.Get("/app.js")->status, 200);
    auto info = std::async(std::launch::async, [&] {
        httplib::Client asking("127.0.0.1", server.port());
        asking.set_read_timeout(60, 0);
        return asking.Get("/api/info");
    });
    // Still held: the request waits (it would have been answered within milliseconds).
    EXPECT_EQ(info.wait_for(std::chrono::milliseconds(300)), std::future_status::timeout);
    release.set_value();
    const auto answered = info.get();
    ASSERT_TRUE(answered);
    EXPECT_EQ(answered->status, 200);
    EXPECT_EQ(nlohmann::json::parse(answered->body)["kind"], "scan");
    EXPECT_NO_THROW(server.wait_until_loaded());
    server.stop();
    serving.join();
}

TEST(ViewServerLoadingTest, AFailedReadingIsTheApisAnswerAndTheCallersError) {
    ViewServer server([]() -> ViewSource { throw FormatError("scan.splat", "header", "a splat file", "other bytes"); }, ViewServerOptions{});
    std::thread serving([&] { server.run(); });
    EXPECT_THROW(server.wait_until_loaded(), FormatError);
    httplib::Client client("127.0.0.1", server.port());
    const auto info = client.Get("/api/info");
    ASSERT_TRUE(info);
    EXPECT_EQ(info->status, 500);
    EXPECT_NE(info->body.find("scan.splat: header"), std::string::npos) << info->body;
    server.stop();
    serving.join();
}

TEST(ViewCommandTest, AnUnreadableInputIsReportedBeforeServing) {
    EXPECT_EQ(cli::run({"view", "/nonexistent/scan.nii", "--no-open", "--quiet"}), cli::kRuntimeError);
    EXPECT_EQ(cli::run({"view", "/nonexistent/mesh.stl", "--no-open", "--quiet"}), cli::kRuntimeError);
}

}  // namespace
}  // namespace vdbmesh
