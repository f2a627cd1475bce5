#pragma once
// The parts of the extension module vdbmesh._vdbmesh, each defined in its own file.

#include <pybind11/pybind11.h>

namespace vdbmesh::python {

/// vdbmesh.Error and vdbmesh.FormatError, and the translation of C++ exceptions (errors.cpp).
void register_errors(pybind11::module_& module);
/// check, read_mesh, write_mesh: meshes as arrays, no OpenVDB (mesh_functions.cpp).
void bind_mesh_functions(pybind11::module_& module);
/// read_volume, mesh_array, mesh_file, array_to_vdb: volumes and grids (volume_functions.cpp).
void bind_volume_functions(pybind11::module_& module);
/// marching_cubes_extras: scikit-image's mask, normals and values (marching_cubes_extras.cpp).
void bind_marching_cubes_extras(pybind11::module_& module);
/// mesh_labels_file, mesh_labels_array: label maps to one mesh per label (label_functions.cpp).
void bind_label_functions(pybind11::module_& module);

}  // namespace vdbmesh::python
