// C++ exceptions as Python ones, with the library's messages:
//   UsageError (a bad argument)               -> ValueError
//   FormatError (input not matching its format) -> vdbmesh.FormatError, a ValueError and a vdbmesh.Error
//   Error (I/O and other runtime failures)     -> vdbmesh.Error, a RuntimeError
//   std::filesystem::filesystem_error          -> OSError
// (A missing input file raises FileNotFoundError before any C++ runs: vdbmesh/__init__.py.)

#include <Python.h>

#include <exception>
#include <filesystem>

#include "bindings.h"
#include "vdbmesh/error.h"

namespace py = pybind11;

namespace vdbmesh::python {

namespace {

// Owned by the module (as its attributes), which is never unloaded.
PyObject* error_type = nullptr;
PyObject* format_error_type = nullptr;

PyObject* new_exception_type(const char* name, PyObject* bases, const char* doc) {
    PyObject* type = PyErr_NewExceptionWithDoc(name, doc, bases, nullptr);
    if (!type) throw py::error_already_set();
    return type;
}

void translate(std::exception_ptr thrown) {
    try {
        std::rethrow_exception(thrown);
    } catch (const FormatError& e) {
        PyErr_SetString(format_error_type, e.what());
    } catch (const Error& e) {
        PyErr_SetString(error_type, e.what());
    } catch (const UsageError& e) {
        PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const std::filesystem::filesystem_error& e) {
        PyErr_SetString(PyExc_OSError, e.what());
    }
}

}  // namespace

void register_errors(py::module_& module) {
    error_type = new_exception_type("vdbmesh.Error", PyExc_RuntimeError,
                                    "A runtime failure of vdbmesh (I/O, bad data); the message says what and where.");
    const py::tuple format_bases = py::make_tuple(py::handle(error_type), py::handle(PyExc_ValueError));
    format_error_type = new_exception_type(
        "vdbmesh.FormatError", format_bases.ptr(),
        "Input that does not match its format; the message names the file (or array), the field, the expected "
        "and the actual value.");
    module.attr("Error") = py::handle(error_type);
    module.attr("FormatError") = py::handle(format_error_type);
    py::register_exception_translator(translate);
}

}  // namespace vdbmesh::python
