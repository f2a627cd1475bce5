#pragma once
// Ctrl-C during a long call. The work runs with the GIL released, so Python's signal handlers
// cannot run until it returns; the progress callbacks the library calls between its steps take
// the GIL and run them, and a handler's exception (KeyboardInterrupt) unwinds the work as a C++
// exception that pybind11 raises again in Python. Outputs are written atomically, so an
// interrupted call leaves no file behind.

#include <functional>

namespace vdbmesh::python {

/// A progress callback (fraction done, ignored) that runs pending Python signal handlers and
/// throws pybind11::error_already_set when one raised. Make it on the thread that calls into
/// the module; it checks only when called from that thread (Python runs handlers only on its
/// main thread, and worker threads must not contend for the GIL).
std::function<void(double)> signal_checking_progress();

}  // namespace vdbmesh::python
