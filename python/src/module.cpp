// The extension module vdbmesh._vdbmesh; vdbmesh/__init__.py is its public face.

#include "bindings.h"

PYBIND11_MODULE(_vdbmesh, module) {
    module.doc() = "vdbmesh's C++ library; use the functions of the vdbmesh package.";
    vdbmesh::python::register_errors(module);
    vdbmesh::python::bind_mesh_functions(module);
    vdbmesh::python::bind_volume_functions(module);
    vdbmesh::python::bind_marching_cubes_extras(module);
    vdbmesh::python::bind_label_functions(module);
}
