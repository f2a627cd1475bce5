// OpenVDB's volumeToMesh (tools/VolumeToMesh.h: a dual contouring close to Nielson's dual
// Marching Cubes, with adaptivity merging blocks whose normals agree), turned into our Mesh.
//
// - Inside: volumeToMesh counts float(value) < float(iso) as inside. Our rule counts a value
//   equal to the isovalue as outside for both sides, so the isovalue handed over is moved to
//   the float for which that holds (matters on integer scans with integer isovalues).
// - Winding: as measured by signed volume (tests/mesh/mesh_grid_test.cpp), volumeToMesh's
//   polygons, read counter-clockwise, face away from the region above the isovalue for level
//   sets and away from the region below it for every other grid class; we reverse them when
//   that region is not the object.
// - Quads are split along the shorter diagonal (the first one on a tie).
// - Boundary: volumeToMesh knows nothing of the scan box: the grid's values are meshed as they
//   are, so on a converted grid (background outside, below the isovalue) the surface is closed
//   by the background beyond the box with inside=above (at the crossing the background value
//   gives, not half a voxel out). With inside=below that background would be inside: the
//   object would be everything but the scanned one, meshed inward. So then a copy is meshed
//   whose values beyond the box are the background mirrored across the isovalue (outside, as
//   far from the isovalue). Where such an object meets the box the surface stays open: the
//   converter made no band there (to it, beyond the box is the object's outside only with
//   inside=above). A scan is therefore converted negated for an object below (side_grid.h),
//   by the command line and the Python module alike; this copy serves a grid converted for
//   the other side (a .vdb written by `convert`). open_boundary is refused by mesh_grid().

#include "mesh/openvdb_mesher.h"

#include "mesh/edge_crossing.h"
#include "vdbmesh/grid.h"

#include <openvdb/tools/VolumeToMesh.h>

#include <cmath>
#include <limits>
#include <utility>

namespace vdbmesh::detail {

namespace {

/// The float s such that, for every float v, volumeToMesh's test v < s is our "outside" test
/// (v <= iso) for Inside::above and our "inside" test (v < iso) for Inside::below.
float volume_to_mesh_isovalue(double iso, Inside inside) {
    constexpr float kInfinity = std::numeric_limits<float>::infinity();
    float s = float(iso);
    if (inside == Inside::above) {
        // v <= iso  <=>  v < s: s is the float after the largest float not above iso.
        if (double(s) > iso) s = std::nextafter(s, -kInfinity);
        return std::nextafter(s, kInfinity);
    }
    // v < iso  <=>  v < s: s is the smallest float not below iso.
    if (double(s) < iso) s = std::nextafter(s, kInfinity);
    return s;
}

/// A copy of @a grid whose values beyond its scanned box are outside the object, or null when
/// they already are (or the grid records no box).
openvdb::FloatGrid::Ptr outside_beyond_box(const openvdb::FloatGrid& grid, const MeshOptions& options) {
    const auto box = stored_scan_box(grid);
    const bool above = options.inside == Inside::above;
    const double background = grid.background();
    if (!box || !is_inside_value(background, options.iso, above)) return nullptr;
    const float outside = float(2 * options.iso - background);
    auto copy = grid.deepCopy();
    // Inside the box no value equals the background (convert_to_grid keeps it below every sample).
    copy->tree().root().setBackground(outside, /*updateChildNodes=*/true);
    for (auto leaf = copy->tree().beginLeaf(); leaf; ++leaf) {
        if (box->isInside(leaf->getNodeBoundingBox())) continue;
        for (openvdb::Index n = 0; n < leaf->SIZE; ++n)
            if (!box->isInside(leaf->offsetToGlobalCoord(n))) leaf->setValueOnly(n, outside);
    }
    return copy;
}

double squared_distance(const openvdb::Vec3s& a, const openvdb::Vec3s& b) { return double((a - b).lengthSqr()); }

}  // namespace

Mesh openvdb_volume_to_mesh(const openvdb::FloatGrid& grid, const MeshOptions& options) {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    const openvdb::FloatGrid::Ptr closed = outside_beyond_box(grid, options);
    openvdb::tools::volumeToMesh(closed ? *closed : grid, points, triangles, quads,
                                 volume_to_mesh_isovalue(options.iso, options.inside), options.adaptivity);
    if (options.progress) options.progress(0.8);

    const bool outward_from_below = grid.getGridClass() != openvdb::GRID_LEVEL_SET;
    const bool reverse = outward_from_below != (options.inside == Inside::below);
    Mesh mesh;
    mesh.vertices.reserve(points.size());
    for (const auto& p : points) mesh.vertices.push_back({p[0], p[1], p[2]});
    mesh.triangles.reserve(triangles.size() + 2 * quads.size());
    auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        if (reverse) std::swap(b, c);
        mesh.triangles.push_back({a, b, c});
    };
    for (const auto& t : triangles) add(t[0], t[1], t[2]);
    for (const auto& q : quads) {
        if (squared_distance(points[q[0]], points[q[2]]) <= squared_distance(points[q[1]], points[q[3]])) {
            add(q[0], q[1], q[2]);
            add(q[0], q[2], q[3]);
        } else {
            add(q[0], q[1], q[3]);
            add(q[1], q[2], q[3]);
        }
    }
    if (options.progress) options.progress(1.0);
    return mesh;
}

}  // namespace vdbmesh::detail
