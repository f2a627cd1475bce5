#pragma once
// What several splat tests share: one definition each, so that the folder builds as one
// translation unit (a unity build: tests/CMakeLists.txt).

#include <openvdb/math/Vec3.h>

#include <array>

namespace vdbmesh::test {

inline constexpr double kPi = 3.14159265358979323846;

/// A splat's float triple (centre, normal) as OpenVDB's double vector.
inline openvdb::Vec3d vec(const std::array<float, 3>& a) { return openvdb::Vec3d(a[0], a[1], a[2]); }

}  // namespace vdbmesh::test
