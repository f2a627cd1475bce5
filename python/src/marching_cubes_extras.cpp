// What skimage.measure.marching_cubes returns beside the mesh, for vdbmesh.marching_cubes
// (python/vdbmesh/_skimage.py): its mask applied per cell, the normals and the values, from a
// Marching Cubes mesh in index space and the samples it was made from. Serial: a few passes
// over the mesh, small beside meshing it.

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "bindings.h"
#include "vdbmesh/error.h"

namespace py = pybind11;

namespace vdbmesh::python {

namespace {

using Index3 = std::array<std::int64_t, 3>;
using Floats = py::array_t<float, py::array::c_style | py::array::forcecast>;
using Faces = py::array_t<std::int32_t, py::array::c_style | py::array::forcecast>;
using Mask = py::array_t<bool, py::array::c_style | py::array::forcecast>;

/// A C-ordered 3D array of samples (or of cell flags), indexed by (i, j, k).
template <typename T>
struct Grid3 {
    const T* data;
    Index3 shape;
    T operator()(const Index3& p) const { return data[(p[0] * shape[1] + p[1]) * shape[2] + p[2]]; }
};

/// The cell (its first corner) of triangle @a f: each vertex lies strictly inside an edge of
/// the cell, so per axis the smallest floor of its corners is the cell's (all three could
/// only share the cell's far face if the triangle lay in it, which Marching Cubes never makes).
/// Clamped to the cells of a grid of @a shape samples, so that no input reads outside it.
Index3 cell_of(const float* vertices, const std::int32_t* f, const Index3& shape) {
    Index3 cell;
    for (int axis = 0; axis < 3; ++axis) {
        float lowest = vertices[3 * f[0] + axis];
        for (int c = 1; c < 3; ++c) lowest = std::min(lowest, vertices[3 * f[c] + axis]);
        cell[axis] = std::clamp<std::int64_t>(std::int64_t(std::floor(lowest)), 0, shape[axis] - 2);
    }
    return cell;
}

/// np.gradient of the samples at sample @a p: central differences, one-sided at the border.
std::array<double, 3> gradient_at(const Grid3<float>& samples, const Index3& p) {
    std::array<double, 3> gradient{};
    for (int axis = 0; axis < 3; ++axis) {
        Index3 before = p, after = p;
        before[axis] = std::max<std::int64_t>(p[axis] - 1, 0);
        after[axis] = std::min<std::int64_t>(p[axis] + 1, samples.shape[axis] - 1);
        if (after[axis] > before[axis])
            gradient[axis] = (double(samples(after)) - samples(before)) / double(after[axis] - before[axis]);
    }
    return gradient;
}

/// The unit normal at a vertex on a grid edge: the gradient at the edge's ends interpolated
/// along it, negated (towards lower values, as scikit-image's).
std::array<float, 3> normal_at(const Grid3<float>& samples, const float* vertex) {
    int axis = 0;  // the coordinate that is not a sample index
    for (int a = 1; a < 3; ++a)
        if (std::abs(vertex[a] - std::round(vertex[a])) > std::abs(vertex[axis] - std::round(vertex[axis]))) axis = a;
    Index3 first;  // clamped into the grid, so that no input reads outside it
    for (int a = 0; a < 3; ++a)
        first[a] = std::clamp<std::int64_t>(std::int64_t(std::round(vertex[a])), 0, samples.shape[a] - 1);
    first[axis] = std::clamp<std::int64_t>(std::int64_t(std::floor(vertex[axis])), 0, samples.shape[axis] - 2);
    Index3 second = first;
    second[axis] += 1;
    const double t = vertex[axis] - double(first[axis]);
    const auto g0 = gradient_at(samples, first), g1 = gradient_at(samples, second);
    std::array<double, 3> g;
    for (int a = 0; a < 3; ++a) g[a] = (1 - t) * g0[a] + t * g1[a];
    const double length = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    const double scale = length > 0 ? -1 / length : 0.0;
    return {float(g[0] * scale), float(g[1] * scale), float(g[2] * scale)};
}

/// max - min of the 8 samples at the corners of @a cell.
float cell_range(const Grid3<float>& samples, const Index3& cell) {
    float lo = samples(cell), hi = lo;
    for (int c = 1; c < 8; ++c) {
        const float v = samples({cell[0] + (c & 1), cell[1] + ((c >> 1) & 1), cell[2] + (c >> 2)});
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    return hi - lo;
}

/// (vertices, faces, normals, values) of the triangles of (@a vertices, @a faces), a Marching
/// Cubes mesh of @a samples in index space, whose cell @a cell_mask keeps (all without one);
/// vertices no kept triangle uses are dropped, the others keep their order. Values: per
/// vertex the largest value range of the cells whose triangles use it (scikit-image's).
py::tuple marching_cubes_extras(const Floats& samples, const Floats& vertices, const Faces& faces,
                                const std::optional<Mask>& cell_mask) {
    if (samples.ndim() != 3 || vertices.ndim() != 2 || vertices.shape(1) != 3 || faces.ndim() != 2 || faces.shape(1) != 3 ||
        samples.shape(0) < 2 || samples.shape(1) < 2 || samples.shape(2) < 2)
        throw UsageError("internal: marching_cubes_extras: expected 3D samples (2 or more along each axis) and N x 3 "
                         "vertices and faces");
    if (cell_mask && (cell_mask->ndim() != 3 || cell_mask->shape(0) != samples.shape(0) - 1 ||
                      cell_mask->shape(1) != samples.shape(1) - 1 || cell_mask->shape(2) != samples.shape(2) - 1))
        throw UsageError("internal: marching_cubes_extras: expected a mask per cell");
    const Grid3<float> grid{samples.data(), {samples.shape(0), samples.shape(1), samples.shape(2)}};
    std::optional<Grid3<bool>> mask;
    if (cell_mask) mask = Grid3<bool>{cell_mask->data(), {cell_mask->shape(0), cell_mask->shape(1), cell_mask->shape(2)}};
    const float* v = vertices.data();
    const std::int32_t* f = faces.data();
    const auto face_count = faces.shape(0), vertex_count = vertices.shape(0);

    std::vector<std::int32_t> kept_faces;
    std::vector<float> kept_ranges;
    std::vector<std::int32_t> renumbered(std::size_t(vertex_count), -1);
    std::vector<float> values;
    {
        py::gil_scoped_release released;
        std::vector<float> vertex_values(std::size_t(vertex_count), 0.0f);
        for (py::ssize_t t = 0; t < face_count; ++t) {
            const Index3 cell = cell_of(v, f + 3 * t, grid.shape);
            if (mask && !(*mask)(cell)) continue;
            const float range = cell_range(grid, cell);
            for (int c = 0; c < 3; ++c) {
                const std::int32_t index = f[3 * t + c];
                if (index < 0 || index >= vertex_count)
                    throw UsageError("internal: marching_cubes_extras: a face index outside the vertices");
                vertex_values[std::size_t(index)] = std::max(vertex_values[std::size_t(index)], range);
                kept_faces.push_back(index);
                renumbered[std::size_t(index)] = 0;
            }
        }
        std::int32_t next = 0;
        for (py::ssize_t i = 0; i < vertex_count; ++i)
            if (renumbered[std::size_t(i)] == 0) {
                renumbered[std::size_t(i)] = next++;
                values.push_back(vertex_values[std::size_t(i)]);
            }
        for (auto& index : kept_faces) index = renumbered[std::size_t(index)];
    }
    const auto kept_vertices = py::ssize_t(values.size());
    Floats out_vertices({kept_vertices, py::ssize_t{3}}), out_normals({kept_vertices, py::ssize_t{3}});
    Faces out_faces({py::ssize_t(kept_faces.size() / 3), py::ssize_t{3}});
    py::array_t<float> out_values(kept_vertices, values.data());
    float* ov = out_vertices.mutable_data();
    float* on = out_normals.mutable_data();
    std::copy(kept_faces.begin(), kept_faces.end(), out_faces.mutable_data());
    {
        py::gil_scoped_release released;
        for (py::ssize_t i = 0; i < vertex_count; ++i) {
            const std::int32_t j = renumbered[std::size_t(i)];
            if (j < 0) continue;
            std::copy(v + 3 * i, v + 3 * i + 3, ov + 3 * j);
            const auto normal = normal_at(grid, v + 3 * i);
            std::copy(normal.begin(), normal.end(), on + 3 * j);
        }
    }
    return py::make_tuple(out_vertices, out_faces, out_normals, out_values);
}

}  // namespace

void bind_marching_cubes_extras(py::module_& module) {
    module.def("marching_cubes_extras", &marching_cubes_extras, py::arg("samples"), py::arg("vertices"),
               py::arg("faces"), py::arg("cell_mask"));
}

}  // namespace vdbmesh::python
