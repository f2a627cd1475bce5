#include "mesh_arrays.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "vdbmesh/error.h"

namespace py = pybind11;

namespace vdbmesh::python {

namespace {

/// An M x 3 array of @a Value over the storage of @a rows, which the array then owns.
template <typename Value, typename Row>
py::array owning_array(std::vector<Row>&& rows) {
    static_assert(sizeof(Row) == 3 * sizeof(Value), "rows are three packed values");
    auto* owned = new std::vector<Row>(std::move(rows));
    py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<Row>*>(p); });
    const auto count = static_cast<py::ssize_t>(owned->size());
    // int32 faces share the bytes of uint32 indices (meshes stay far below 2^31 vertices).
    return py::array_t<Value>({count, py::ssize_t{3}}, reinterpret_cast<const Value*>(owned->data()), owner);
}

template <typename T>
py::array_t<T, py::array::c_style | py::array::forcecast> rows_of_three(const py::array& array, const char* what) {
    auto cast = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(array);
    if (!cast || cast.ndim() != 2 || cast.shape(1) != 3)
        throw UsageError(std::string(what) + ": expected an N x 3 numeric array");
    return cast;
}

}  // namespace

py::tuple to_arrays(Mesh&& mesh) {
    return py::make_tuple(owning_array<float>(std::move(mesh.vertices)),
                          owning_array<std::int32_t>(std::move(mesh.triangles)));
}

Mesh from_arrays(const py::array& vertices, const py::array& faces) {
    const auto v = rows_of_three<float>(vertices, "vertices");
    const auto f = rows_of_three<std::int64_t>(faces, "faces");
    Mesh mesh;
    mesh.vertices.resize(static_cast<std::size_t>(v.shape(0)));
    std::memcpy(mesh.vertices.data(), v.data(), mesh.vertices.size() * sizeof(mesh.vertices[0]));
    mesh.triangles.resize(static_cast<std::size_t>(f.shape(0)));
    const std::int64_t* indices = f.data();
    const auto vertex_count = static_cast<std::int64_t>(mesh.vertices.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c) {
            const std::int64_t index = indices[3 * t + c];
            if (index < 0 || index >= vertex_count)
                throw UsageError("faces: expected vertex indices in [0, " + std::to_string(vertex_count) + "), got " +
                                 std::to_string(index) + " in face " + std::to_string(t));
            mesh.triangles[t][c] = static_cast<std::uint32_t>(index);
        }
    return mesh;
}

}  // namespace vdbmesh::python
