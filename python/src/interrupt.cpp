#include "interrupt.h"

#include <pybind11/pybind11.h>

#include <thread>

namespace py = pybind11;

namespace vdbmesh::python {

std::function<void(double)> signal_checking_progress() {
    const std::thread::id caller = std::this_thread::get_id();
    return [caller](double) {
        if (std::this_thread::get_id() != caller) return;
        py::gil_scoped_acquire acquired;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    };
}

}  // namespace vdbmesh::python
