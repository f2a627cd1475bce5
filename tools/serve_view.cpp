#include "serve_view.h"

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <thread>

namespace vdbmesh::cli {
namespace {

volatile std::sig_atomic_t g_stop_requested = 0;

extern "C" void request_stop(int) { g_stop_requested = 1; }

/// Hands @a address to the desktop's browser, when there is one.
void open_browser(const std::string& address) {
    if (std::system("command -v xdg-open >/dev/null 2>&1") != 0) return;
    const std::string command = "xdg-open '" + address + "' >/dev/null 2>&1 &";
    if (std::system(command.c_str()) != 0) std::cerr << "vdbmesh view: could not open a browser\n";
}

/// Announces @a server, hands its address to the browser unless @a no_open, serves in a thread
/// until SIGINT or SIGTERM, then stops it and returns. Rethrows (after stopping it) what its
/// source's loading threw (ViewServer's constructor taking a loader).
void serve_until_interrupted(ViewServer& server, const std::string& input, bool no_open, bool quiet) {
    // Before the address is announced: a Ctrl-C right after it (a script that stops the server
    // as soon as it serves) stops it cleanly instead of killing it.
    std::signal(SIGINT, request_stop);
    std::signal(SIGTERM, request_stop);
    std::cout << "vdbmesh view: serving " << input << " at " << server.address() << " (Ctrl-C to stop)" << std::endl;
    if (!no_open) open_browser(server.address());
    std::thread serving([&server] { server.run(); });
    try {
        server.wait_until_loaded();
    } catch (...) {
        server.stop();
        serving.join();
        throw;
    }
    while (!g_stop_requested) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    server.stop();
    serving.join();
    if (!quiet) std::cerr << "vdbmesh view: stopped\n";
}

}  // namespace

void serve_view(ViewSource source, const ViewServerOptions& options, const std::string& input, bool no_open, bool quiet) {
    ViewServer server(std::move(source), options);
    serve_until_interrupted(server, input, no_open, quiet);
}

void serve_view_while_loading(std::function<ViewSource()> load, const ViewServerOptions& options, const std::string& input,
                              bool no_open, bool quiet) {
    ViewServer server(std::move(load), options);
    serve_until_interrupted(server, input, no_open, quiet);
}

}  // namespace vdbmesh::cli
