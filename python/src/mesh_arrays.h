#pragma once
// Meshes as numpy arrays: vertices N x 3 float32, faces M x 3 int32.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "vdbmesh/mesh.h"

namespace vdbmesh::python {

/// (vertices, faces) taking over the mesh's buffers, without copying them.
pybind11::tuple to_arrays(Mesh&& mesh);

/// A Mesh copied from (vertices, faces) arrays of any numeric type (cast to float32 and
/// uint32). Throws UsageError on a wrong shape or a face index outside the vertices.
Mesh from_arrays(const pybind11::array& vertices, const pybind11::array& faces);

}  // namespace vdbmesh::python
