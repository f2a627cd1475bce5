// `vdbmesh view scan.vdb --splats FILE`: the splat tree fitted once into its file, read back
// on the next run, refused when the file belongs to another grid; and the server showing it.
// `vdbmesh view scan.splat`: the file alone, its splats served, what needs the grid refused.

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>
#include <chrono>
#include <fstream>
#include <future>
#include <iterator>
#include <thread>

#include "cli.h"
#include "phantom_grid.h"
#include "splat_camera.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/splats.h"
#include "vdbmesh/view.h"
#include "view_splat_file.h"

namespace vdbmesh {
namespace {

constexpr double kIso = 0.5;  // the phantom's surface

std::string file_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// A sphere phantom of @a size^3 written as a .vdb at @a path.
void write_sphere(const std::filesystem::path& path, int size) {
    write_vdb(*test::phantom_scan_grid(phantom_preset("sphere", {size, size, size})), path);
}

std::shared_ptr<const ViewSplats> splats_for(const std::filesystem::path& file, const std::filesystem::path& vdb,
                                             std::optional<double> asked_iso = std::nullopt) {
    return cli::view_splat_file(file, vdb, *open_vdb_regions(vdb), asked_iso, kIso, /*quiet=*/true);
}

TEST(ViewSplatFile, FittedOnceThenReadFromTheFile) {
    const test::ScratchDir dir;
    write_sphere(dir / "scan.vdb", 40);
    const auto fitted = splats_for(dir / "scan.splat", dir / "scan.vdb");
    EXPECT_FALSE(fitted->from_file);
    ASSERT_TRUE(std::filesystem::exists(dir / "scan.splat"));
    SplatOptions options;
    options.iso = kIso;
    const SplatTree expected = build_splat_tree(*open_vdb_regions(dir / "scan.vdb"), options);
    ASSERT_GT(expected.nodes.size(), 100u);
    EXPECT_EQ(fitted->tree->nodes.size(), expected.nodes.size());
    const std::string written = file_bytes(dir / "scan.splat");

    const auto read = splats_for(dir / "scan.splat", dir / "scan.vdb");
    EXPECT_TRUE(read->from_file);
    EXPECT_EQ(read->tree->iso, kIso);
    ASSERT_EQ(read->tree->nodes.size(), expected.nodes.size());
    for (std::size_t i = 0; i < expected.nodes.size(); ++i) {
        EXPECT_EQ(read->tree->nodes[i].child_count, expected.nodes[i].child_count);
        EXPECT_EQ(read->tree->nodes[i].weight, expected.nodes[i].weight);
    }
    EXPECT_EQ(file_bytes(dir / "scan.splat"), written);  // read, not rewritten
    // Asking for its own isovalue is fine; another one is a usage error naming both.
    EXPECT_TRUE(splats_for(dir / "scan.splat", dir / "scan.vdb", kIso)->from_file);
    try {
        splats_for(dir / "scan.splat", dir / "scan.vdb", 0.25);
        ADD_FAILURE() << "no error for another isovalue";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("--iso 0.25: " + (dir / "scan.splat").string() + " holds the splat tree at 0.5"),
                  std::string::npos) << e.what();
    }
}

TEST(ViewSplatFile, AFileOfAnotherOrAlteredGridIsRefusedAndKept) {
    const test::ScratchDir dir;
    write_sphere(dir / "a.vdb", 40);
    write_sphere(dir / "b.vdb", 48);
    splats_for(dir / "a.splat", dir / "a.vdb");
    const std::string kept = file_bytes(dir / "a.splat");
    const auto expect_refused = [&](const std::filesystem::path& vdb) {
        try {
            splats_for(dir / "a.splat", vdb);
            ADD_FAILURE() << "no error for " << vdb;
        } catch (const UsageError&) {
            ADD_FAILURE() << "a usage error for " << vdb;
        } catch (const Error& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find((dir / "a.splat").string() + ": fitted to another grid than " + vdb.string() + " (the grid it was fitted to states checksum"),
                      std::string::npos) << message;
            EXPECT_NE(message.find("remove it to fit"), std::string::npos) << message;
        }
        EXPECT_EQ(file_bytes(dir / "a.splat"), kept);
    };
    expect_refused(dir / "b.vdb");
    // a.vdb altered: one sample changed, written again (its stated checksum changes).
    auto grid = test::phantom_scan_grid(phantom_preset("sphere", {40, 40, 40}));
    grid->tree().setValue(openvdb::Coord(20, 20, 20), 0.75f);
    write_vdb(*grid, dir / "a.vdb");
    expect_refused(dir / "a.vdb");
}

// With an existing splat file the page is served while it is read: the refusal ends the command
// (status 1) and answers the page's requests; nothing of the grid is served.
TEST(ViewSplatFile, TheCommandRefusesAndWritesNothing) {
    const test::ScratchDir dir;
    write_sphere(dir / "a.vdb", 40);
    write_sphere(dir / "b.vdb", 48);
    splats_for(dir / "b.splat", dir / "b.vdb");
    const std::string kept = file_bytes(dir / "b.splat");
    EXPECT_EQ(cli::run({"view", (dir / "a.vdb").string(), "--splats", (dir / "b.splat").string(), "--no-open", "--quiet"}),
              cli::kRuntimeError);
    EXPECT_EQ(file_bytes(dir / "b.splat"), kept);
    // Not a splat file (the grid itself named by mistake): refused, untouched.
    const std::string grid = file_bytes(dir / "b.vdb");
    EXPECT_EQ(cli::run({"view", (dir / "a.vdb").string(), "--splats", (dir / "b.vdb").string(), "--no-open", "--quiet"}),
              cli::kRuntimeError);
    EXPECT_EQ(file_bytes(dir / "b.vdb"), grid);
    EXPECT_EQ(cli::run({"view", (dir / "b.vdb").string(), "--splats", (dir / "b.splat").string(), "--iso", "0.3", "--no-open", "--quiet"}),
              cli::kUsageError);
    EXPECT_EQ(cli::run({"view", (dir / "scan.nii").string(), "--splats", (dir / "s.splat").string(), "--no-open", "--quiet"}),
              cli::kUsageError);
    EXPECT_FALSE(std::filesystem::exists(dir / "s.splat"));
}

TEST(ViewSplatFile, TheServerShowsTheTreeMadeBeforeServing) {
    const test::ScratchDir dir;
    write_sphere(dir / "scan.vdb", 40);
    splats_for(dir / "scan.splat", dir / "scan.vdb");
    auto regions = std::shared_ptr<const GridRegionSource>(open_vdb_regions(dir / "scan.vdb"));
    ViewSource source;
    source.name = "scan.vdb";
    source.splats = cli::view_splat_file(dir / "scan.splat", dir / "scan.vdb", *regions, std::nullopt, kIso, true);
    source.scan = std::make_shared<const ViewScan>(prepare_grid_regions(regions));
    source.initial_iso = kIso;
    ViewServer server(source, {});
    std::thread serving([&] { server.run(); });
    httplib::Client client("127.0.0.1", server.port());
    const auto info = nlohmann::json::parse(client.Get("/api/info")->body);
    EXPECT_EQ(info["splats"]["from_file"], true);
    EXPECT_EQ(info["splats"]["nodes"], source.splats->tree->nodes.size());
    const SplatView camera = test::camera_at({20, 20, 2000}, openvdb::Vec3d(20, 20, 20));
    std::string vp;
    for (double v : camera.view_projection) vp += (vp.empty() ? "" : ",") + std::to_string(v);
    const auto response = client.Get(("/api/splats?vp=" + vp + "&eye=20,20,2000&focal=" + std::to_string(camera.focal_pixels)).c_str());
    ASSERT_TRUE(response);
    EXPECT_EQ(response->status, 200) << response->body;
    // The file's tree, not a fit: its node count and the seconds it took to read.
    EXPECT_EQ(response->get_header_value("X-Tree-Nodes"), std::to_string(source.splats->tree->nodes.size()));
    EXPECT_EQ(response->get_header_value("X-Seconds"), std::to_string(source.splats->seconds));
    EXPECT_EQ(response->body.size(), 28 * select_splats(*source.splats->tree, camera).nodes.size());
    server.stop();
    serving.join();
}

TEST(ViewSplatFile, TheSplatsAreServedWhileTheScanIsPrepared) {
    const test::ScratchDir dir;
    write_sphere(dir / "scan.vdb", 40);
    auto regions = std::shared_ptr<const GridRegionSource>(open_vdb_regions(dir / "scan.vdb"));
    ViewSource source;
    source.name = "scan.vdb";
    source.splats = cli::view_splat_file(dir / "scan.splat", dir / "scan.vdb", *regions, std::nullopt, kIso, true);
    source.initial_iso = kIso;
    std::promise<void> release;
    source.prepare_scan = [regions, held = release.get_future().share()](const BackgroundControl& control) {
        held.wait();  // the pass over the grid, held until the test has asked its questions
        return std::make_shared<const ViewScan>(prepare_grid_regions(regions, &control));
    };
    ViewServer server(source, {});
    std::thread serving([&] { server.run(); });
    httplib::Client client("127.0.0.1", server.port());
    auto info = nlohmann::json::parse(client.Get("/api/info")->body);
    EXPECT_EQ(info["kind"], "scan");
    EXPECT_EQ(info["preparing"], true);
    EXPECT_FALSE(info.contains("scan"));
    for (int a = 0; a < 3; ++a) EXPECT_LT(info["splats"]["box_min"][a].get<double>(), info["splats"]["box_max"][a].get<double>());
    const SplatView camera = test::camera_at({20, 20, 2000}, openvdb::Vec3d(20, 20, 20));
    std::string query = "/api/splats?vp=";
    for (std::size_t i = 0; i < camera.view_projection.size(); ++i) query += (i ? "," : "") + std::to_string(camera.view_projection[i]);
    query += "&eye=20,20,2000&focal=" + std::to_string(camera.focal_pixels);
    const auto splats = client.Get(query.c_str());
    ASSERT_TRUE(splats);
    EXPECT_EQ(splats->status, 200) << splats->body;
    EXPECT_EQ(splats->get_header_value("X-Tree-Nodes"), std::to_string(source.splats->tree->nodes.size()));
    // What needs the prepared scan answers 503 meanwhile: a mesh, the splats of another isovalue.
    EXPECT_EQ(client.Get("/api/mesh?level=coarse")->status, 503);
    EXPECT_EQ(client.Get((query + "&iso=0.3").c_str())->status, 503);

    release.set_value();
    info = nlohmann::json::parse(client.Get("/api/info?prepare=1")->body);  // the page's word: its first splats are drawn
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (info.contains("preparing") && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        info = nlohmann::json::parse(client.Get("/api/info")->body);
    }
    ASSERT_FALSE(info.contains("preparing"));
    EXPECT_EQ(info["scan"]["initial_iso"], kIso);
    EXPECT_GT(info["scan"]["histogram"].size(), 0u);
    const auto coarse = client.Get("/api/mesh?level=coarse");
    ASSERT_TRUE(coarse);
    EXPECT_EQ(coarse->status, 200) << coarse->body;
    EXPECT_GT(std::stoull(coarse->get_header_value("X-Triangles")), 100u);
    server.stop();
    serving.join();
}

/// The query of GET /api/splats for test::camera_at(@a eye) looking at the sphere's centre.
std::string splat_query(const std::array<double, 3>& eye) {
    return test::splat_query(test::camera_at(eye, openvdb::Vec3d(20, 20, 20)), 480000);
}

TEST(ViewSplatFile, ASplatFileAloneIsShownWithoutItsGrid) {
    const test::ScratchDir dir;
    write_sphere(dir / "scan.vdb", 40);
    const auto fitted = splats_for(dir / "scan.splat", dir / "scan.vdb");
    std::filesystem::remove(dir / "scan.vdb");  // the splats alone, as when only the file was copied
    ViewSource source;
    source.name = "scan.splat";
    source.splats = cli::view_splats_alone(dir / "scan.splat", std::nullopt, /*quiet=*/true);
    source.initial_iso = source.splats->tree->iso;
    EXPECT_EQ(source.splats->tree->nodes.size(), fitted->tree->nodes.size());
    EXPECT_EQ(source.splats->tree->iso, kIso);
    for (int a = 0; a < 3; ++a) EXPECT_LT(source.splats->box_min[a], source.splats->box_max[a]);
    ViewServer server(source, {});
    std::thread serving([&] { server.run(); });
    httplib::Client client("127.0.0.1", server.port());
    const auto info = nlohmann::json::parse(client.Get("/api/info")->body);
    EXPECT_EQ(info["kind"], "splats");
    EXPECT_FALSE(info.contains("scan"));
    EXPECT_FALSE(info.contains("preparing"));
    EXPECT_EQ(info["splats"]["nodes"], fitted->tree->nodes.size());
    // Close enough for a close-up of a grid: none without the grid, the splats all the same.
    const std::string query = splat_query({20, 20, 45});
    const auto splats = client.Get(query.c_str());
    ASSERT_TRUE(splats);
    EXPECT_EQ(splats->status, 200) << splats->body;
    EXPECT_GT(std::stoull(splats->get_header_value("X-Splats")), 0u);
    EXPECT_FALSE(splats->has_header("X-Closeup-Box"));
    // What needs the grid is refused, saying so: a mesh, a download, the splats of another isovalue.
    const std::vector<std::string> needing_the_grid{"/api/mesh?level=coarse", "/api/download?format=stl", query + "&iso=0.3"};
    for (const std::string& refused : needing_the_grid) {
        const auto response = client.Get(refused.c_str());
        ASSERT_TRUE(response) << refused;
        EXPECT_EQ(response->status, 400) << refused;
        EXPECT_NE(response->body.find("a splat file alone has no grid"), std::string::npos) << refused << ": " << response->body;
    }
    server.stop();
    serving.join();
}

TEST(ViewSplatFile, ASplatFileAloneRefusesWhatNeedsTheGrid) {
    const test::ScratchDir dir;
    write_sphere(dir / "scan.vdb", 40);
    splats_for(dir / "scan.splat", dir / "scan.vdb");
    const std::string splat = (dir / "scan.splat").string();
    const std::vector<std::vector<std::string>> usages{
        {"--iso", "0.3"}, {"--labels", "all"}, {"--splats", (dir / "b.splat").string()}, {"--raw-dims", "4,4,4"}, {(dir / "scan.vdb").string()}};
    for (const auto& usage : usages) {
        std::vector<std::string> arguments{"view", splat, "--no-open", "--quiet"};
        arguments.insert(arguments.end(), usage.begin(), usage.end());
        EXPECT_EQ(cli::run(arguments), cli::kUsageError) << usage.front();
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "b.splat"));
    std::filesystem::copy_file(dir / "scan.vdb", dir / "grid.splat");  // not a splat file
    EXPECT_EQ(cli::run({"view", (dir / "grid.splat").string(), "--no-open", "--quiet"}), cli::kRuntimeError);
    EXPECT_THROW(cli::view_splats_alone(dir / "grid.splat", std::nullopt, true), FormatError);
    EXPECT_EQ(cli::run({"view", (dir / "missing.splat").string(), "--no-open", "--quiet"}), cli::kRuntimeError);
}

}  // namespace
}  // namespace vdbmesh
