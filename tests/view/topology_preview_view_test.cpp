// `vdbmesh view scan.vdb` without a splat file: the topology preview served at once, the tree
// fitted in the background served in its place, then the scan's preparation.

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>
#include <chrono>
#include <thread>

#include "phantom_grid.h"
#include "splat_camera.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/splats.h"
#include "vdbmesh/view.h"

namespace vdbmesh {
namespace {

constexpr double kIso = 0.5;  // the phantom's surface

/// The page's query for a camera at @a eye looking at the sphere's centre, asking for close-ups.
std::string splat_query(const std::array<double, 3>& eye) {
    return test::splat_query(test::camera_at(eye, openvdb::Vec3d(20, 20, 20)), 480000);
}

TEST(ViewTopologyPreview, ThePreviewIsServedThenTheFittedTreeInItsPlace) {
    const test::ScratchDir dir;
    write_vdb(*test::phantom_scan_grid(phantom_preset("sphere", {40, 40, 40})), dir / "scan.vdb");
    auto regions = std::shared_ptr<const GridRegionSource>(open_vdb_regions(dir / "scan.vdb"));
    ViewSource source;  // as `vdbmesh view scan.vdb` makes it
    source.name = "scan.vdb";
    source.splats = topology_preview_splats(*regions, kIso);
    source.initial_iso = kIso;
    source.fit_splats = [regions](const BackgroundControl& control) { return fit_view_splats(regions, kIso, control); };
    source.prepare_scan = [regions](const BackgroundControl& control) {
        return std::make_shared<const ViewScan>(prepare_grid_regions(regions, &control));
    };
    EXPECT_TRUE(source.splats->preview);
    EXPECT_EQ(source.splats->tree->leaf_count(), regions->active_leaves({{-1000, -1000, -1000}, {1000, 1000, 1000}}).size());
    ViewServer server(source, {});
    std::thread serving([&] { server.run(); });
    httplib::Client client("127.0.0.1", server.port());
    // Before the page's word (its first splats drawn), neither the fit nor the pass has begun.
    auto info = nlohmann::json::parse(client.Get("/api/info")->body);
    EXPECT_EQ(info["splats"]["preview"], true);
    EXPECT_EQ(info["preparing"], true);
    const std::string near = splat_query({20, 20, 45});  // close: a fitted tree's close-up
    auto splats = client.Get(near.c_str());
    ASSERT_TRUE(splats);
    EXPECT_EQ(splats->status, 200) << splats->body;
    EXPECT_EQ(splats->get_header_value("X-Splat-Kind"), "preview");
    EXPECT_EQ(splats->get_header_value("X-Tree-Nodes"), std::to_string(source.splats->tree->nodes.size()));
    EXPECT_FALSE(splats->has_header("X-Closeup-Box"));  // the preview's weights are no crossings

    info = nlohmann::json::parse(client.Get("/api/info?prepare=1")->body);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (info.contains("preparing") && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        info = nlohmann::json::parse(client.Get("/api/info")->body);
    }
    ASSERT_FALSE(info.contains("preparing"));
    EXPECT_FALSE(info.contains("prepare_error")) << info.dump();
    EXPECT_EQ(info["splats"]["preview"], false);
    SplatOptions options;
    options.iso = kIso;
    const SplatTree fitted = build_splat_tree(*regions, options);
    splats = client.Get(near.c_str());
    ASSERT_TRUE(splats);
    EXPECT_EQ(splats->status, 200) << splats->body;
    EXPECT_EQ(splats->get_header_value("X-Splat-Kind"), "fitted");
    EXPECT_EQ(splats->get_header_value("X-Tree-Nodes"), std::to_string(fitted.nodes.size()));
    EXPECT_NE(fitted.nodes.size(), source.splats->tree->nodes.size());
    EXPECT_EQ(client.Get("/api/mesh?level=coarse")->status, 200);
    server.stop();
    serving.join();
}

TEST(ViewTopologyPreview, AStoppedFitGivesUpBeforeItsNextRead) {
    const test::ScratchDir dir;
    write_vdb(*test::phantom_scan_grid(phantom_preset("sphere", {40, 40, 40})), dir / "scan.vdb");
    BackgroundControl stopped;
    stopped.stop();
    try {
        fit_view_splats(open_vdb_regions(dir / "scan.vdb"), kIso, stopped);
        ADD_FAILURE() << "a stopped fit went on";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("the splat tree's fit was stopped"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace vdbmesh
