#pragma once
// Serving a page of `vdbmesh view` until Ctrl-C: for `view` and for `lattice --view`.

#include <functional>
#include <string>

#include "vdbmesh/view.h"

namespace vdbmesh::cli {

/// Serves @a source on @a options' address, announces it on stdout (naming @a input), hands the
/// address to the desktop's browser unless @a no_open, and returns after SIGINT or SIGTERM.
void serve_view(ViewSource source, const ViewServerOptions& options, const std::string& input, bool no_open, bool quiet);

/// The same, served at once while @a load makes the source (the browser starts meanwhile; the
/// page waits for the source). Throws what @a load throws, after stopping the server.
void serve_view_while_loading(std::function<ViewSource()> load, const ViewServerOptions& options, const std::string& input,
                              bool no_open, bool quiet);

}  // namespace vdbmesh::cli
