// check, read_mesh, write_mesh: meshes given and returned as numpy arrays.

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>

#include "bindings.h"
#include "mesh_arrays.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/mesh_io.h"

namespace py = pybind11;

namespace vdbmesh::python {

namespace {

/// The figures of `vdbmesh check --json`, under the same names.
py::dict analysis_dict(const MeshAnalysis& r) {
    py::dict d;
    d["clean"] = r.is_clean();
    d["triangles"] = r.triangles;
    d["vertices"] = r.vertices;
    d["unreferenced_vertices"] = r.unreferenced_vertices;
    d["edges"] = r.edges;
    d["boundary_edges"] = r.boundary_edges;
    d["boundary_loops"] = r.boundary_loops;
    d["nonmanifold_edges"] = r.nonmanifold_edges;
    d["nonmanifold_vertices"] = r.nonmanifold_vertices;
    d["misoriented_edges"] = r.misoriented_edges;
    d["degenerate_faces"] = r.degenerate_faces;
    d["repeated_vertex_faces"] = r.repeated_vertex_faces;
    d["zero_area_faces"] = r.zero_area_faces;
    d["self_intersecting_pairs"] = r.self_intersecting_pairs;
    d["components"] = r.components;
    d["euler_characteristic"] = r.euler_characteristic;
    d["genus"] = r.genus;
    d["closed"] = r.closed;
    d["outward"] = r.outward;
    d["negative_components"] = r.negative_components;
    d["area"] = r.area;
    d["volume"] = r.volume;
    d["centroid"] = r.centroid;
    d["inertia"] = r.inertia;
    d["min_angle_deg"] = r.min_angle_deg;
    d["small_angle_share"] = r.small_angle_share;
    return d;
}

py::dict check(const py::array& vertices, const py::array& faces) {
    const Mesh mesh = from_arrays(vertices, faces);
    MeshAnalysis analysis;
    {
        py::gil_scoped_release released;
        analysis = analyze_mesh(mesh);
    }
    return analysis_dict(analysis);
}

py::tuple read_mesh_arrays(const std::filesystem::path& path) {
    Mesh mesh;
    {
        py::gil_scoped_release released;
        mesh = read_mesh(path);
    }
    return to_arrays(std::move(mesh));
}

void write_mesh_arrays(const std::filesystem::path& path, const py::array& vertices, const py::array& faces, bool ascii,
                       bool normals) {
    const Mesh mesh = from_arrays(vertices, faces);
    py::gil_scoped_release released;
    write_mesh(mesh, path, MeshWriteOptions{ascii, normals});
}

}  // namespace

void bind_mesh_functions(py::module_& module) {
    module.def("check", &check, py::arg("vertices"), py::arg("faces"));
    module.def("read_mesh", &read_mesh_arrays, py::arg("path"));
    module.def("write_mesh", &write_mesh_arrays, py::arg("path"), py::arg("vertices"), py::arg("faces"),
               py::arg("ascii"), py::arg("normals"));
}

}  // namespace vdbmesh::python
