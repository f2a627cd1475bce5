// The clip solid of a lattice: a closed mesh as a narrow-band level set (OpenVDB's
// meshToLevelSet), in the lattice's voxels.

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include "vdbmesh/error.h"
#include "vdbmesh/lattice.h"

namespace vdbmesh {

std::shared_ptr<openvdb::FloatGrid> clip_level_set(const Mesh& solid, double voxel, double band_voxels) {
    if (solid.triangles.empty()) throw UsageError("--clip: expected a closed solid, got an empty mesh");
    const auto transform = openvdb::math::Transform::createLinearTransform(voxel);
    std::vector<openvdb::Vec3s> points(solid.vertices.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const openvdb::Vec3d p = transform->worldToIndex(openvdb::Vec3d(solid.vertices[i][0], solid.vertices[i][1], solid.vertices[i][2]));
        points[i] = openvdb::Vec3s(float(p[0]), float(p[1]), float(p[2]));
    }
    std::vector<openvdb::Vec3I> triangles(solid.triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        triangles[i] = openvdb::Vec3I(solid.triangles[i][0], solid.triangles[i][1], solid.triangles[i][2]);
    }
    const float width = float(band_voxels + 1.0);
    return openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, triangles, width);
}

}  // namespace vdbmesh
