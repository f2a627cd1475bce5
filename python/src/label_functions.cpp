// mesh_labels_file, mesh_labels_array: a label map (a scan file or an integer array) to one
// closed mesh per label with shared walls (include/vdbmesh/labels.h, issue 31).

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "axis_order.h"
#include "bindings.h"
#include "mesh_arrays.h"
#include "vdbmesh/error.h"
#include "vdbmesh/labels.h"

namespace py = pybind11;

namespace vdbmesh::python {
namespace {

using LabelArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

LabelMeshOptions label_options(const std::vector<std::uint32_t>& labels, int smoothing_iterations) {
    LabelMeshOptions options;
    options.labels = labels;
    options.smoothing_iterations = smoothing_iterations;
    return options;
}

/// {label: (vertices, faces)} in ascending label order.
py::dict label_dict(LabelSurface&& surface) {
    py::dict result;
    std::vector<Mesh> meshes;
    {
        py::gil_scoped_release released;
        meshes = label_meshes(surface);
    }
    for (std::size_t i = 0; i < meshes.size(); ++i) result[py::int_(surface.labels[i])] = to_arrays(std::move(meshes[i]));
    return result;
}

py::dict mesh_labels_file(const std::filesystem::path& path, const std::vector<std::uint32_t>& labels, int smoothing_iterations) {
    const LabelMeshOptions options = label_options(labels, smoothing_iterations);
    LabelSurface surface;
    {
        py::gil_scoped_release released;
        auto reader = open_volume(path);
        surface = mesh_labels(read_label_volume(*reader), options);
    }
    return label_dict(std::move(surface));
}

/// array[i, j, k] (C order, so k is fastest: vdbmesh's x) as a label volume.
LabelVolume array_labels(const LabelArray& array, const Affine& array_to_world) {
    if (array.ndim() != 3) throw UsageError("labels: expected a 3D integer array, got " + std::to_string(array.ndim()) + "D");
    LabelVolume volume;
    volume.header.path = "array";
    volume.header.format = "array";
    volume.header.dims = reversed(std::array<std::int64_t, 3>{array.shape(0), array.shape(1), array.shape(2)});
    volume.header.index_to_world = swap_i_and_k(array_to_world);
    const std::int64_t* data = array.data();
    volume.labels.resize(std::size_t(array.size()));
    for (std::size_t n = 0; n < volume.labels.size(); ++n) {
        if (data[n] < 0 || data[n] > std::int64_t(kMaxLabel)) {
            const std::size_t k = n % std::size_t(array.shape(2)), j = n / std::size_t(array.shape(2)) % std::size_t(array.shape(1)),
                              i = n / std::size_t(array.shape(2) * array.shape(1));
            throw UsageError("labels: array[" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) +
                             "]: expected a label 0.." + std::to_string(kMaxLabel) + ", got " + std::to_string(data[n]));
        }
        volume.labels[n] = std::uint16_t(data[n]);
    }
    return volume;
}

py::dict mesh_labels_array(const LabelArray& array, const Affine& array_to_world, const std::vector<std::uint32_t>& labels,
                           int smoothing_iterations) {
    const LabelMeshOptions options = label_options(labels, smoothing_iterations);
    const LabelVolume volume = array_labels(array, array_to_world);
    LabelSurface surface;
    {
        py::gil_scoped_release released;
        surface = mesh_labels(volume, options);
    }
    return label_dict(std::move(surface));
}

}  // namespace

void bind_label_functions(py::module_& module) {
    module.def("mesh_labels_file", &mesh_labels_file, py::arg("path"), py::arg("labels"), py::arg("smoothing_iterations"));
    module.def("mesh_labels_array", &mesh_labels_array, py::arg("array"), py::arg("array_to_world"), py::arg("labels"),
               py::arg("smoothing_iterations"));
}

}  // namespace vdbmesh::python
