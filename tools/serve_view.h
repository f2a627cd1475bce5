#pragma once
// Serving a page of `vdbmesh view` until Ctrl-C: for `view` and for `lattice --view`.

#include <string>

#include "vdbmesh/view.h"

namespace vdbmesh::cli {

/// Serves @a source on @a options' address, announces it on stdout (naming @a input), hands the
/// address to the desktop's browser unless @a no_open, and returns after SIGINT or SIGTERM.
void serve_view(ViewSource source, const ViewServerOptions& options, const std::string& input, bool no_open, bool quiet);

}  // namespace vdbmesh::cli
