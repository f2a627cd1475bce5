// The server's background work pauses while the page's camera moves (POST /api/motion, issue
// 30's frame time): a paused preparation reads nothing more until the camera is still, then
// finishes with what an unpaused one gives; a pause the page never ends lapses by itself.

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>
#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include "phantom_grid.h"
#include "vdbmesh/background_control.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/phantom.h"
#include "vdbmesh/view.h"

namespace vdbmesh {
namespace {

constexpr double kIso = 0.5;  // the phantom's surface
/// The bound of every wait for the server: far above what the work takes (well under a second).
constexpr std::chrono::seconds kPatience{60};
/// How long "no progress" is watched: the work, when not paused, reads its next slab in
/// microseconds here, so a read within this time would show.
constexpr std::chrono::milliseconds kWatched{300};

/// A source that counts its reads and can hold one of them (the test then acts while the work
/// is inside it).
class HoldingRegions : public GridRegionSource {
public:
    HoldingRegions(std::shared_ptr<const GridRegionSource> source, int held_read)
        : source_(std::move(source)), held_read_(held_read), released_(release_.get_future().share()) {}
    std::shared_ptr<const openvdb::FloatGrid> description() const override { return source_->description(); }
    std::vector<NodeWeight> nodes() const override { return source_->nodes(); }
    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox& box) const override {
        if (++reads == held_read_) {
            entered_.set_value();
            released_.wait();
        }
        return source_->read(box);
    }
    std::uint64_t estimated_bytes(const IndexBox& box) const override { return source_->estimated_bytes(box); }
    /// Resolves once the held read has begun.
    std::future<void> entered() { return entered_.get_future(); }
    void release() { release_.set_value(); }
    mutable std::atomic<int> reads{0};

private:
    std::shared_ptr<const GridRegionSource> source_;
    int held_read_;
    mutable std::promise<void> entered_;
    std::promise<void> release_;
    std::shared_future<void> released_;
};

/// A grid of four slabs one node thick (the preparation reads it slab by slab).
std::shared_ptr<const GridRegionSource> four_slabs() {
    PhantomSpec spec = phantom_preset("cylinder", {48, 48, 480});
    spec.radius = 17;
    spec.height = 440;
    return grid_regions_in_memory(test::phantom_scan_grid(spec));
}

/// A server preparing @a regions in the background, as `view scan.vdb --splats FILE` does (the
/// topology preview of @a shown stands for the splats: made before, none of @a regions' reads);
/// @a prepared receives the scan it made.
ViewSource preparing(std::shared_ptr<const GridRegionSource> regions, const GridRegionSource& shown,
                     std::promise<std::shared_ptr<const ViewScan>>& prepared) {
    ViewSource source;
    source.name = "scan.vdb";
    source.splats = topology_preview_splats(shown, kIso);
    source.initial_iso = kIso;
    source.prepare_scan = [regions, &prepared](const BackgroundControl& control) {
        auto scan = std::make_shared<const ViewScan>(prepare_grid_regions(regions, &control));
        prepared.set_value(scan);
        return scan;
    };
    return source;
}

int motion(httplib::Client& client, const char* moving) {
    const auto response = client.Post((std::string("/api/motion?moving=") + moving).c_str(), "", "text/plain");
    return response ? response->status : -1;
}

/// Whether /api/info says the preparation is over, waiting at most kPatience.
bool prepared_within_patience(httplib::Client& client) {
    const auto deadline = std::chrono::steady_clock::now() + kPatience;
    while (std::chrono::steady_clock::now() < deadline) {
        if (!nlohmann::json::parse(client.Get("/api/info")->body).contains("preparing")) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
}

void expect_same_scan(const ViewScan& scan, const ViewScan& expected) {
    EXPECT_EQ(scan.histogram.min, expected.histogram.min);
    EXPECT_EQ(scan.histogram.max, expected.histogram.max);
    EXPECT_EQ(scan.histogram.counts, expected.histogram.counts);
    EXPECT_EQ(scan.suggested_iso, expected.suggested_iso);
    EXPECT_EQ(scan.coarse_factor, expected.coarse_factor);
    ASSERT_EQ(scan.coarse->activeVoxelCount(), expected.coarse->activeVoxelCount());
    const auto values = expected.coarse->getConstAccessor();
    for (auto voxel = scan.coarse->cbeginValueOn(); voxel; ++voxel)
        ASSERT_EQ(*voxel, values.getValue(voxel.getCoord())) << voxel.getCoord();
}

TEST(ViewMotion, APausedPreparationReadsNothingMoreAndFinishesTheSame) {
    const auto regions = four_slabs();
    const ViewScan expected = prepare_grid_regions(regions);
    auto holding = std::make_shared<HoldingRegions>(regions, /*held_read=*/2);
    std::promise<std::shared_ptr<const ViewScan>> prepared;
    ViewServerOptions options;
    options.motion_lease = std::chrono::minutes(10);  // ended by moving=0 only, however slow the machine
    options.resume_after_still = std::chrono::milliseconds(0);
    ViewServer server(preparing(holding, *regions, prepared), options);
    std::thread serving([&] { server.run(); });
    httplib::Client client("127.0.0.1", server.port());
    auto entered = holding->entered();
    ASSERT_EQ(client.Get("/api/info?prepare=1")->status, 200);  // starts the preparation
    // The camera starts moving while the work is inside its second read.
    ASSERT_EQ(entered.wait_for(kPatience), std::future_status::ready);
    EXPECT_EQ(motion(client, "1"), 200);
    holding->release();
    std::this_thread::sleep_for(kWatched);
    EXPECT_EQ(holding->reads, 2);  // that slab's work stops at its next checkpoint: no third read
    EXPECT_TRUE(nlohmann::json::parse(client.Get("/api/info")->body).contains("preparing"));
    std::this_thread::sleep_for(kWatched);
    EXPECT_EQ(holding->reads, 2);
    // The camera still: the work goes on from where it paused.
    EXPECT_EQ(motion(client, "0"), 200);
    ASSERT_TRUE(prepared_within_patience(client));
    EXPECT_GT(holding->reads, 2);
    expect_same_scan(*prepared.get_future().get(), expected);
    server.stop();
    serving.join();
}

TEST(ViewMotion, APausedPreparationDoesNotStartUntilTheCameraIsStill) {
    const auto regions = four_slabs();
    auto holding = std::make_shared<HoldingRegions>(regions, /*held_read=*/0);  // none held
    std::promise<std::shared_ptr<const ViewScan>> prepared;
    ViewServerOptions options;
    options.motion_lease = std::chrono::minutes(10);
    options.resume_after_still = std::chrono::milliseconds(0);
    ViewServer server(preparing(holding, *regions, prepared), options);
    std::thread serving([&] { server.run(); });
    httplib::Client client("127.0.0.1", server.port());
    EXPECT_EQ(motion(client, "1"), 200);
    ASSERT_EQ(client.Get("/api/info?prepare=1")->status, 200);  // starts the preparation
    std::this_thread::sleep_for(kWatched);
    EXPECT_EQ(holding->reads, 0);
    EXPECT_EQ(motion(client, "0"), 200);
    ASSERT_TRUE(prepared_within_patience(client));
    expect_same_scan(*prepared.get_future().get(), prepare_grid_regions(regions));
    server.stop();
    serving.join();
}

TEST(ViewMotion, APauseThePageNeverEndsLapsesByItself) {
    const auto regions = four_slabs();
    std::promise<std::shared_ptr<const ViewScan>> prepared;
    ViewServerOptions options;
    options.motion_lease = std::chrono::milliseconds(50);  // a page gone while its camera moved
    ViewServer server(preparing(regions, *regions, prepared), options);
    std::thread serving([&] { server.run(); });
    httplib::Client client("127.0.0.1", server.port());
    EXPECT_EQ(motion(client, "1"), 200);
    ASSERT_EQ(client.Get("/api/info?prepare=1")->status, 200);  // starts the preparation
    EXPECT_TRUE(prepared_within_patience(client));  // no moving=0 ever comes
    server.stop();
    serving.join();
}

TEST(ViewMotion, TheMotionIsOneOrZero) {
    std::promise<std::shared_ptr<const ViewScan>> prepared;
    const auto regions = four_slabs();
    ViewServer server(preparing(regions, *regions, prepared), {});
    std::thread serving([&] { server.run(); });
    httplib::Client client("127.0.0.1", server.port());
    for (const char* bad : {"", "yes", "2"}) {
        const auto response = client.Post((std::string("/api/motion?moving=") + bad).c_str(), "", "text/plain");
        ASSERT_TRUE(response);
        EXPECT_EQ(response->status, 400) << bad;
        EXPECT_NE(response->body.find("moving: expected 1 or 0"), std::string::npos) << response->body;
    }
    const auto response = client.Post("/api/motion?moving=1", "", "text/plain");
    ASSERT_TRUE(response);
    EXPECT_EQ(nlohmann::json::parse(response->body)["paused_ms"], 3000);
    server.stop();
    serving.join();
}

TEST(BackgroundControl, ACheckpointWaitsOutAPauseAndThrowsOnceStopped) {
    BackgroundControl control;
    control.checkpoint("the work");  // neither paused nor stopped: at once
    EXPECT_EQ(control.waits(), 0u);
    control.pause_until(BackgroundControl::Clock::now() + std::chrono::minutes(10));
    std::atomic<bool> passed{false};
    std::thread work([&] {
        control.checkpoint("the work");
        passed = true;
    });
    std::this_thread::sleep_for(kWatched);
    EXPECT_FALSE(passed);
    control.resume();
    work.join();
    EXPECT_TRUE(passed);
    EXPECT_EQ(control.waits(), 1u);
    // A stop ends a pause at once, with the work's own words.
    control.pause_until(BackgroundControl::Clock::now() + std::chrono::minutes(10));
    std::promise<std::string> stopped;
    std::thread stopped_work([&] {
        try {
            control.checkpoint("the splat tree's fit");
            stopped.set_value("no error");
        } catch (const Error& e) {
            stopped.set_value(e.what());
        }
    });
    control.stop();
    stopped_work.join();
    EXPECT_EQ(stopped.get_future().get(), "the splat tree's fit was stopped");
}

}  // namespace
}  // namespace vdbmesh
