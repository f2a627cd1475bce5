#pragma once
// What several splat tests share: one definition each, so that the folder builds as one
// translation unit (a unity build: tests/CMakeLists.txt).

#include <gtest/gtest.h>
#include <openvdb/math/Vec3.h>

#include <array>
#include <cstddef>

#include "vdbmesh/splats.h"

namespace vdbmesh::test {

inline constexpr double kPi = 3.14159265358979323846;

/// A splat's float triple (centre, normal) as OpenVDB's double vector.
inline openvdb::Vec3d vec(const std::array<float, 3>& a) { return openvdb::Vec3d(a[0], a[1], a[2]); }

/// Expects node @a i of a tree, @a got, to be @a want but for where its children are (which
/// the callers compare themselves: a pruned tree's finest nodes have none).
inline void expect_same_splat(const SplatNode& got, const SplatNode& want, std::size_t i) {
    EXPECT_EQ(got.centre, want.centre) << i;
    EXPECT_EQ(got.normal, want.normal) << i;
    EXPECT_EQ(got.radius, want.radius) << i;
    EXPECT_EQ(got.cone, want.cone) << i;
    EXPECT_EQ(got.weight, want.weight) << i;
    EXPECT_EQ(got.level, want.level) << i;
}

}  // namespace vdbmesh::test
