#pragma once
// Test helper: the camera the page sends for GET /api/splats, made as three.js makes it.

#include <openvdb/openvdb.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>

#include "vdbmesh/splats.h"

namespace vdbmesh::test {

/// three.js's camera at @a eye looking at @a target (up +y), fov 45 degrees, 900 x 700.
inline SplatView camera_at(const std::array<double, 3>& eye, const openvdb::Vec3d& target = openvdb::Vec3d(0)) {
    const openvdb::Vec3d e(eye[0], eye[1], eye[2]);
    const openvdb::Vec3d back = (e - target).unitSafe(), right = openvdb::Vec3d(0, 1, 0).cross(back).unitSafe(), up = back.cross(right);
    const double fov = 45 * 3.14159265358979323846 / 180, aspect = 900.0 / 700.0, near = 0.1, far = 1e6;
    const double f = 1 / std::tan(fov / 2);
    // Row-major view (world to camera) and projection, multiplied, then stored column-major.
    const double view[4][4] = {{right.x(), right.y(), right.z(), -right.dot(e)},
                               {up.x(), up.y(), up.z(), -up.dot(e)},
                               {back.x(), back.y(), back.z(), -back.dot(e)},
                               {0, 0, 0, 1}};
    const double proj[4][4] = {{f / aspect, 0, 0, 0},
                               {0, f, 0, 0},
                               {0, 0, (far + near) / (near - far), 2 * far * near / (near - far)},
                               {0, 0, -1, 0}};
    SplatView camera;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            double sum = 0;
            for (int k = 0; k < 4; ++k) sum += proj[r][k] * view[k][c];
            camera.view_projection[c * 4 + r] = sum;
        }
    camera.eye = eye;
    camera.focal_pixels = 700 / (2 * std::tan(fov / 2));
    return camera;
}

/// The page's query of GET /api/splats for @a camera, asking for close-ups within @a closeup
/// triangles.
inline std::string splat_query(const SplatView& camera, std::uint64_t closeup) {
    std::string query = "/api/splats?vp=";
    for (std::size_t i = 0; i < camera.view_projection.size(); ++i) query += (i ? "," : "") + std::to_string(camera.view_projection[i]);
    query += "&eye=" + std::to_string(camera.eye[0]) + "," + std::to_string(camera.eye[1]) + "," + std::to_string(camera.eye[2]);
    return query + "&focal=" + std::to_string(camera.focal_pixels) + "&closeup=" + std::to_string(closeup);
}

}  // namespace vdbmesh::test
