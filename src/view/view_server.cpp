// ViewServer: the routes of `vdbmesh view` over cpp-httplib.

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <thread>

#include <unistd.h>

#include "vdbmesh/mesh_io.h"
#include "vdbmesh/error.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/shared_splats.h"
#include "vdbmesh/view.h"
#include "view/close_up.h"
#include "view/mesh_buffers.h"
#include "view/mesh_store.h"
#include "view/region_mesh.h"
#include "view/splat_store.h"
#include "view/view_json.h"
#include "view/web_assets.h"

namespace vdbmesh {

namespace {

using Handler = std::function<void(const httplib::Request&, httplib::Response&)>;

void send_error(httplib::Response& response, int status, const std::string& message) {
    response.status = status;
    response.set_content(detail::json_text(nlohmann::json{{"error", message}}), "application/json");
}

/// @a handler, with a usage error answered 400 and any other failure 500, as JSON.
Handler guarded(Handler handler) {
    return [handler = std::move(handler)](const httplib::Request& request, httplib::Response& response) {
        try {
            handler(request, response);
        } catch (const UsageError& e) {
            send_error(response, 400, e.what());
        } catch (const view::ScanPreparing& e) {
            send_error(response, 503, e.what());
        } catch (const view::Superseded& e) {
            send_error(response, 409, e.what());
        } catch (const view::FullMeshOverBudget& e) {
            response.set_header("X-Triangles", std::to_string(e.estimate));
            response.set_header("X-Estimated", "1");
            send_error(response, 413, e.what());
        } catch (const std::exception& e) {
            send_error(response, 500, e.what());
        }
    };
}

view::ParamLookup params_of(const httplib::Request& request) {
    return [&request](const std::string& name) -> std::optional<std::string> {
        if (!request.has_param(name.c_str())) return std::nullopt;
        return request.get_param_value(name.c_str());
    };
}

/// The mesh as write_mesh() writes a file of extension @a format (binary, PLY and OBJ with
/// normals), through a temporary file.
std::string encode_mesh(const Mesh& mesh, const std::string& format) {
    if (format != "stl" && format != "ply" && format != "obj") {
        throw UsageError("format: expected stl|ply|obj, got \"" + format + "\"");
    }
    static std::atomic<unsigned> downloads{0};
    const std::filesystem::path path = std::filesystem::temp_directory_path() /
        ("vdbmesh-view-" + std::to_string(::getpid()) + "-" + std::to_string(++downloads) + "." + format);
    write_mesh(mesh, path, MeshWriteOptions{false, true});
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    std::filesystem::remove(path);
    return bytes;
}

}  // namespace

class ViewServer::Impl {
public:
    Impl(ViewSource source, const ViewServerOptions& options) : options_(options) {
        add_routes();
        bind();
        set_source(std::move(source));
    }

    Impl(std::function<ViewSource()> load, const ViewServerOptions& options) : options_(options) {
        add_routes();
        bind();
        loading_ = std::thread([this, load = std::move(load)] {
            try {
                set_source(load());
            } catch (...) {
                const std::lock_guard<std::mutex> lock(load_mutex_);
                load_error_ = std::current_exception();
                loaded_wake_.notify_all();
            }
        });
    }

    ~Impl() {
        if (loading_.joinable()) loading_.join();
        background_.stop();
        start_preparing();  // wakes a preparation still waiting to start
        if (preparing_.joinable()) preparing_.join();
    }

    void wait_until_loaded() const { loaded(); }

    int port() const { return port_; }
    std::string address() const { return "http://" + options_.host + ":" + std::to_string(port_) + "/"; }
    void run() {
        {
            const std::lock_guard<std::mutex> lock(run_mutex_);
            if (stopping_) return;
            running_ = true;
        }
        server_.listen_after_bind();
        finished_ = true;
    }

    /// httplib's stop() does nothing before the server listens, so a stop() right after run()
    /// began waits for the listening to start (or for run() to have ended).
    void stop() {
        {
            const std::lock_guard<std::mutex> lock(run_mutex_);
            stopping_ = true;
            if (!running_) return;
        }
        while (!server_.is_running() && !finished_) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        server_.stop();
    }

private:
    /// SO_REUSEADDR only: httplib's default adds SO_REUSEPORT, with which a second server
    /// would share a port in use instead of failing.
    static void exclusive_port(socket_t socket) {
        const int yes = 1;
        setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    }

    void bind() {
        server_.set_socket_options(exclusive_port);
        port_ = options_.port;
        if (options_.port == 0) {
            port_ = server_.bind_to_any_port(options_.host);
        } else if (!server_.bind_to_port(options_.host, options_.port)) {
            port_ = -1;
        }
        if (port_ < 0) {
            throw Error("cannot listen on " + options_.host + " port " + std::to_string(options_.port) +
                        ": the port is in use or the address is not this machine's (try another --port, or 0 for any free one)");
        }
    }

    /// Lets the preparation start (the page has drawn its first splats).
    void start_preparing() {
        const std::lock_guard<std::mutex> lock(prepare_mutex_);
        start_preparing_ = true;
        prepare_wake_.notify_all();
    }

    /// Runs ViewSource::prepare_scan (in its thread) and hands the scan to the stores. It waits
    /// for the page's word that its first picture is drawn (GET /api/info?prepare=1), at most
    /// kPrepareDelay: the pass over the grid takes every core, and would hold the page back.
    void prepare_scan() {
        {
            std::unique_lock<std::mutex> lock(prepare_mutex_);
            prepare_wake_.wait_for(lock, kPrepareDelay, [this] { return start_preparing_; });
        }
        if (background_.stopped()) return;
        try {
            // The fitted tree first: the page shows the topology preview until then.
            if (const auto& fit = store().source().fit_splats) splats().set_initial(fit(background_));
            const auto scan = store().source().prepare_scan(background_);
            splats().set_scan(scan);
            store().set_scan(scan);
        } catch (const std::exception& e) {
            const std::lock_guard<std::mutex> lock(prepare_error_mutex_);
            prepare_error_ = e.what();
        }
    }

    nlohmann::json info() {
        ViewSource now = store().source();
        now.scan = store().scan();
        if (auto initial = splats().initial()) now.splats = std::move(initial);  // fitted in place of the preview
        nlohmann::json j = view::info_json(now, options_.triangle_budget);
        if (now.prepare_scan && !now.scan) j["preparing"] = true;
        const std::lock_guard<std::mutex> lock(prepare_error_mutex_);
        if (!prepare_error_.empty()) j["prepare_error"] = prepare_error_;
        return j;
    }

    void add_routes() {
        server_.set_keep_alive_timeout(1);
        server_.Get("/", guarded([this](const auto& request, auto& response) { serve_asset(request, response); }));
        server_.Get("/index.html", guarded([this](const auto& request, auto& response) { serve_asset(request, response); }));
        server_.Get("/app.js", guarded([this](const auto& request, auto& response) { serve_asset(request, response); }));
        server_.Get("/api/info", guarded([this](const auto& request, auto& response) {
            if (request.has_param("prepare")) start_preparing();
            response.set_content(detail::json_text(info()), "application/json");
        }));
        server_.Get("/api/mesh", guarded([this](const auto& request, auto& response) { serve_mesh(request, response); }));
        server_.Get("/api/figures", guarded([this](const auto& request, auto& response) { serve_figures(request, response); }));
        server_.Get("/api/splats", guarded([this](const auto& request, auto& response) { serve_splats(request, response); }));
        server_.Get("/api/download", guarded([this](const auto& request, auto& response) { serve_download(request, response); }));
        server_.Post("/api/motion", guarded([this](const auto& request, auto& response) { serve_motion(request, response); }));
    }

    /// The page's camera started (or goes on) moving, or has come to rest: the background work
    /// pauses meanwhile, its cores left to the browser's drawing (view.h).
    void serve_motion(const httplib::Request& request, httplib::Response& response) {
        const std::string moving = request.has_param("moving") ? request.get_param_value("moving") : "";
        if (moving != "1" && moving != "0") throw UsageError("moving: expected 1 or 0, got \"" + moving + "\"");
        const std::chrono::milliseconds pause = moving == "1" ? options_.motion_lease : options_.resume_after_still;
        background_.pause_until(BackgroundControl::Clock::now() + pause);
        response.set_content(detail::json_text(nlohmann::json{{"paused_ms", pause.count()}}), "application/json");
    }

    void serve_asset(const httplib::Request& request, httplib::Response& response) const {
        const auto asset = view::web_asset(request.path);
        response.set_content(asset->body.data(), asset->body.size(), asset->content_type);
    }

    /// A splat file viewed alone (`view scan.splat`): no grid to mesh or to fit at another isovalue.
    bool splats_alone() const {
        const ViewSource& source = store().source();
        return source.splats && !source.scan && !source.prepare_scan;
    }

    view::MeshRequest parse(const httplib::Request& request) const {
        if (store().source().lattice) throw UsageError("a lattice is shown by its splats only (GET /api/splats)");
        if (splats_alone()) throw UsageError(kNoGrid);
        return view::parse_mesh_request(params_of(request), store().source().initial_iso);
    }

    std::shared_ptr<view::StoredMesh> requested_mesh(const httplib::Request& request) { return store().mesh(parse(request)); }

    void serve_mesh(const httplib::Request& request, httplib::Response& response) {
        const view::MeshRequest parsed = parse(request);
        const auto stored = store().mesh(parsed);
        response.set_header("X-Triangles", std::to_string(stored->mesh->triangles.size()));
        if (parsed.max_triangles && stored->mesh->triangles.size() > *parsed.max_triangles) {
            send_error(response, 413, "the mesh has more triangles than max_triangles");
            return;
        }
        const std::string body = view::mesh_buffers(*stored->mesh);
        response.set_header("X-Vertices", std::to_string(stored->mesh->vertices.size()));
        response.set_header("X-Seconds", std::to_string(stored->seconds));
        response.set_header("Cache-Control", "no-store");
        response.set_content(body, "application/octet-stream");
    }

    void serve_figures(const httplib::Request& request, httplib::Response& response) {
        const auto stored = requested_mesh(request);
        nlohmann::json j;
        j["triangles"] = stored->mesh->triangles.size();
        j["vertices"] = stored->mesh->vertices.size();
        j["seconds"] = stored->seconds;
        j["check"] = nlohmann::json::parse(stored->figures(options_.mesh_figures));
        response.set_content(detail::json_text(j), "application/json");
    }

    void serve_splats(const httplib::Request& request, httplib::Response& response) {
        const view::SplatRequest parsed = view::parse_splat_request(params_of(request), store().source().initial_iso);
        if (const auto& lattice = store().source().lattice) {
            const SharedSplatSelection selection = select_splats(*lattice->splats, parsed.view);
            set_splat_headers(response, selection.summary, selection.nodes.size(), lattice->splats->represented_nodes(), lattice->seconds);
            response.set_content(view::splat_buffers(selection.nodes), "application/octet-stream");
            return;
        }
        if (splats_alone() && parsed.iso != store().source().initial_iso)
            throw UsageError("iso: the splat file holds the splats at " + std::to_string(store().source().initial_iso) + " only; " + kNoGrid);
        const auto stored = splats().tree(parsed.iso);
        SplatSelection selection = select_splats(*stored->tree, parsed.view);
        // The preview's weights count active voxels, not crossings: no close-up's estimate from them.
        if (parsed.close_up_triangles && !stored->preview) add_close_up(*stored, parsed, selection, response);
        set_splat_headers(response, selection, selection.nodes.size(), stored->tree->nodes.size(), stored->seconds);
        response.set_header("X-Splat-Kind", stored->preview ? "preview" : "fitted");
        response.set_content(view::splat_buffers(*stored->tree, selection), "application/octet-stream");
    }

    static void set_splat_headers(httplib::Response& response, const SplatSelection& selection, std::size_t shown,
                                  std::uint64_t tree_nodes, double seconds) {
        response.set_header("X-Splats", std::to_string(shown));
        response.set_header("X-Level", std::to_string(selection.finest_level));
        response.set_header("X-Cut-Level", std::to_string(selection.cut_level));
        response.set_header("X-Complete", selection.complete ? "1" : "0");
        response.set_header("X-Tree-Nodes", std::to_string(tree_nodes));
        response.set_header("X-Seconds", std::to_string(seconds));
        response.set_header("Cache-Control", "no-store");
    }

    /// The close-up the view asks for, if any, in headers: X-Closeup-Box (x0,y0,z0,x1,y1,z1, for
    /// GET /api/mesh?level=region), X-Closeup-Triangles (estimated) and X-Closeup-Splats (the
    /// selection's last nodes, whose centres lie in the box: the triangles replace them). None
    /// when the close-up would read more than a close-up may.
    void add_close_up(const view::StoredSplats& stored, const view::SplatRequest& request, SplatSelection& selection,
                      httplib::Response& response) const {
        const auto scan = store().scan();
        if (!scan) return;  // the close-up's mesh waits for the scan's preparation
        const GridRegionSource& regions = *scan->regions;
        const auto grid = regions.description();
        const auto close = view::find_close_up(*stored.tree, selection, request.view, *grid, *request.close_up_triangles);
        if (!close || regions.estimated_bytes(view::region_read_box(close->box)) > options_.region_read_bytes) return;
        std::string box;
        for (auto bound : {close->box.min, close->box.max})
            for (std::int32_t v : bound) box += (box.empty() ? "" : ",") + std::to_string(v);
        response.set_header("X-Closeup-Box", box);
        response.set_header("X-Closeup-Triangles", std::to_string(close->estimated_triangles));
        response.set_header("X-Closeup-Splats", std::to_string(view::move_inside_last(*stored.tree, close->box, *grid, selection)));
    }

    void serve_download(const httplib::Request& request, httplib::Response& response) {
        const std::string format = request.has_param("format") ? request.get_param_value("format") : "stl";
        const auto stored = requested_mesh(request);
        const std::string body = encode_mesh(*stored->mesh, format);
        response.set_header("Content-Disposition", "attachment; filename=\"mesh." + format + "\"");
        response.set_content(body, "application/octet-stream");
    }

    /// What serves the source, made once it is there.
    struct Loaded {
        Loaded(ViewSource source, const ViewServerOptions& options)
            : store(std::move(source), options.mesher, options.triangle_budget, options.region_read_bytes),
              splats(store.source().scan, store.source().splats, store.source().initial_iso, options.other_splat_tree_bytes) {}
        view::MeshStore store;
        view::SplatStore splats;
    };

    void set_source(ViewSource source) {
        auto loaded = std::make_unique<Loaded>(std::move(source), options_);
        const bool prepare = bool(loaded->store.source().prepare_scan);
        {
            const std::lock_guard<std::mutex> lock(load_mutex_);
            loaded_ = std::move(loaded);
            loaded_wake_.notify_all();
        }
        if (prepare) preparing_ = std::thread([this] { prepare_scan(); });
    }

    /// The stores, once the source is there (the page's API requests wait for it); rethrows
    /// the loading's failure.
    Loaded& loaded() const {
        std::unique_lock<std::mutex> lock(load_mutex_);
        loaded_wake_.wait(lock, [this] { return loaded_ || load_error_; });
        if (load_error_) std::rethrow_exception(load_error_);
        return *loaded_;
    }
    view::MeshStore& store() const { return loaded().store; }
    view::SplatStore& splats() const { return loaded().splats; }

    static constexpr const char* kNoGrid =
        "a splat file alone has no grid to mesh or fit: view the .vdb it was fitted to with --splats FILE for meshes, "
        "the isovalue and close-ups";
    ViewServerOptions options_;
    std::thread loading_;  ///< makes the source (the constructor taking a loader)
    mutable std::mutex load_mutex_;
    mutable std::condition_variable loaded_wake_;
    std::unique_ptr<Loaded> loaded_;
    std::exception_ptr load_error_;
    httplib::Server server_;
    int port_ = 0;
    std::mutex run_mutex_;
    bool stopping_ = false, running_ = false;
    std::atomic<bool> finished_{false};
    std::thread preparing_;  ///< runs ViewSource::prepare_scan
    static constexpr std::chrono::seconds kPrepareDelay{20};
    std::mutex prepare_mutex_;
    std::condition_variable prepare_wake_;
    bool start_preparing_ = false;
    BackgroundControl background_;  ///< the fit's and the preparation's: paused while the camera moves, stopped on closing
    std::mutex prepare_error_mutex_;
    std::string prepare_error_;
};

ViewServer::ViewServer(ViewSource source, const ViewServerOptions& options)
    : impl_(std::make_unique<Impl>(std::move(source), options)) {}
ViewServer::ViewServer(std::function<ViewSource()> load, const ViewServerOptions& options)
    : impl_(std::make_unique<Impl>(std::move(load), options)) {}
ViewServer::~ViewServer() = default;
void ViewServer::wait_until_loaded() const { impl_->wait_until_loaded(); }
int ViewServer::port() const { return impl_->port(); }
std::string ViewServer::address() const { return impl_->address(); }
void ViewServer::run() { impl_->run(); }
void ViewServer::stop() { impl_->stop(); }

}  // namespace vdbmesh
