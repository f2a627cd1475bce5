// measure_labels(): volume, area and centroid of each label's closed mesh (divergence theorem).

#include <cmath>

#include "vdbmesh/labels.h"

namespace vdbmesh {
namespace {

double voxel_volume(const Affine& m) {
    return std::abs(m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                    m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]));
}

LabelMeasure measure_mesh_of(const Mesh& mesh) {
    LabelMeasure m;
    std::array<double, 3> moment{};
    for (const auto& t : mesh.triangles) {
        std::array<std::array<double, 3>, 3> p;
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) p[i][k] = mesh.vertices[t[i]][k];
        const std::array<double, 3> e1{p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
        const std::array<double, 3> e2{p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
        const std::array<double, 3> c{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        m.area += 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        // Signed volume of the tetrahedron (origin, p0, p1, p2) and its centroid's moment.
        const double v = (p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) - p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                          p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0])) / 6;
        m.volume += v;
        for (int k = 0; k < 3; ++k) moment[k] += v * (p[0][k] + p[1][k] + p[2][k]) / 4;
    }
    if (m.volume != 0)
        for (int k = 0; k < 3; ++k) m.centroid[k] = moment[k] / m.volume;
    m.triangles = mesh.triangles.size();
    return m;
}

}  // namespace

std::vector<LabelMeasure> measure_labels(const LabelSurface& surface, const LabelVolume& volume) {
    std::vector<std::uint64_t> voxels(std::size_t(kMaxLabel) + 1, 0);
    for (const LabelCount& count : count_labels(volume)) voxels[count.value] = count.voxels;
    const double one_voxel = voxel_volume(volume.header.index_to_world);
    std::vector<LabelMeasure> result;
    const std::vector<Mesh> meshes = label_meshes(surface);
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const std::uint32_t label = surface.labels[i];
        LabelMeasure m = measure_mesh_of(meshes[i]);
        m.value = label;
        m.voxels = voxels[label];
        m.voxel_volume = double(m.voxels) * one_voxel;
        result.push_back(m);
    }
    return result;
}

}  // namespace vdbmesh
