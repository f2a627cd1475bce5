// measure_mesh(): what `vdbmesh measure` reports. The integrals come from analyze_mesh()
// (integrals.cpp: divergence theorem over the triangles, as in chapter 3.3 of shared seed 002);
// the principal moments and axes are the eigen-decomposition of the inertia tensor.
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

#include "analysis/measure_parts.h"
#include "vdbmesh/measure.h"

namespace vdbmesh {
namespace {

using Vec = std::array<double, 3>;
using Mat = std::array<Vec, 3>;

/// Sign convention of an axis: its largest-magnitude coordinate is positive.
Vec canonical_sign(Vec axis) {
    int largest = 0;
    for (int k = 1; k < 3; ++k) {
        if (std::abs(axis[k]) > std::abs(axis[largest])) largest = k;
    }
    if (axis[largest] < 0) {
        for (double& x : axis) x = -x;
    }
    return axis;
}

}  // namespace

namespace detail {

void set_principal_frame(const Mat& inertia, MeshMeasure& measure) {
    Eigen::Matrix3d tensor;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) tensor(i, j) = inertia[i][j];
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(tensor);  // ascending eigenvalues
    for (int k = 0; k < 3; ++k) {
        measure.principal_moments[k] = solver.eigenvalues()(k);
        const Eigen::Vector3d axis = solver.eigenvectors().col(k);
        measure.principal_axes[k] = canonical_sign({axis(0), axis(1), axis(2)});
    }
    const Vec& a = measure.principal_axes[0];
    const Vec& b = measure.principal_axes[1];
    measure.principal_axes[2] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

void sort_components(std::vector<ComponentMeasure>& components) {
    std::stable_sort(components.begin(), components.end(), [](const ComponentMeasure& a, const ComponentMeasure& b) {
        if (std::abs(a.volume) != std::abs(b.volume)) return std::abs(a.volume) > std::abs(b.volume);
        return a.area > b.area;
    });
}

}  // namespace detail

namespace {

void set_bounding_box(const Mesh& mesh, MeshMeasure& measure) {
    if (mesh.triangles.empty()) return;
    measure.box_min.fill(std::numeric_limits<double>::infinity());
    measure.box_max.fill(-std::numeric_limits<double>::infinity());
    for (const auto& triangle : mesh.triangles) {
        for (const std::uint32_t v : triangle) {
            for (int k = 0; k < 3; ++k) {
                measure.box_min[k] = std::min(measure.box_min[k], double(mesh.vertices[v][k]));
                measure.box_max[k] = std::max(measure.box_max[k], double(mesh.vertices[v][k]));
            }
        }
    }
}

std::vector<ComponentMeasure> measure_components(const Mesh& mesh) {
    std::vector<ComponentMeasure> components;
    for (const Mesh& component : split_components(mesh)) {
        const MeshIntegrals integrals = mesh_integrals(component);
        components.push_back({component.triangles.size(), integrals.area, integrals.volume});
    }
    detail::sort_components(components);
    return components;
}

}  // namespace

MeshMeasure measure_mesh(const Mesh& mesh) {
    MeshMeasure measure;
    measure.report = analyze_mesh(mesh);
    detail::set_principal_frame(measure.report.inertia, measure);
    set_bounding_box(mesh, measure);
    measure.components = measure_components(mesh);
    return measure;
}

}  // namespace vdbmesh
