#pragma once
// Analytic test grids for the mesher tests, their options, and the few mesh checks analysis.h
// does not make.

#include <openvdb/openvdb.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <set>

#include "vdbmesh/analysis.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::test {

inline constexpr double kPi = 3.14159265358979323846;

/// Options for meshing with @a method at @a iso, everything else left at its default.
inline MeshOptions mesh_options(MeshMethod method, double iso, Inside inside = Inside::above) {
    MeshOptions options;
    options.method = method;
    options.iso = iso;
    options.inside = inside;
    return options;
}

/// Vertices whose coordinates equal those of another vertex.
inline std::size_t coincident_vertices(const Mesh& mesh) {
    std::set<std::array<float, 3>> seen(mesh.vertices.begin(), mesh.vertices.end());
    return mesh.vertices.size() - seen.size();
}

/// Signed volume: positive when a closed mesh's normals point out.
inline double signed_volume(const Mesh& mesh) { return mesh_integrals(mesh).volume; }

/// A grid holding field(i, j, k) as active voxels over @a box, @a background elsewhere.
inline openvdb::FloatGrid::Ptr make_grid(const openvdb::CoordBBox& box, const std::function<float(int, int, int)>& field,
                                         float background) {
    auto grid = openvdb::FloatGrid::create(background);
    auto accessor = grid->getAccessor();
    for (auto it = box.begin(); it; ++it) accessor.setValue(*it, field((*it).x(), (*it).y(), (*it).z()));
    return grid;
}

/// Density of a ball: radius - distance to @a centre (positive inside, a signed distance).
inline openvdb::FloatGrid::Ptr make_ball(double radius, const std::array<double, 3>& centre) {
    const int reach = int(std::ceil(radius)) + 3;
    const openvdb::CoordBBox box(openvdb::Coord(int(centre[0]) - reach, int(centre[1]) - reach, int(centre[2]) - reach),
                                 openvdb::Coord(int(centre[0]) + reach, int(centre[1]) + reach, int(centre[2]) + reach));
    return make_grid(box, [&](int i, int j, int k) {
        const double dx = i - centre[0], dy = j - centre[1], dz = k - centre[2];
        return float(radius - std::sqrt(dx * dx + dy * dy + dz * dz));
    }, -float(reach));
}

}  // namespace vdbmesh::test
