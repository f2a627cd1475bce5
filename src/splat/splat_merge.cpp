// Inner nodes of the splat tree: the weighted mean of their children (QSplat), and the test
// that lets a parent stand for coplanar children.

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "splat/splat_build.h"

namespace vdbmesh::splat {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d vec(const std::array<float, 3>& a) { return {a[0], a[1], a[2]}; }

std::array<float, 3> floats(const Eigen::Vector3d& v) {
    return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

/// atan2 rather than acos: accurate for nearly parallel directions.
double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace

BuildNode merge_children(const BuildNode* children, std::uint32_t count, const std::array<std::int32_t, 3>& origin) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero(), normal_sum = Eigen::Vector3d::Zero();
    double total = 0;
    std::uint64_t weight = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
        const double w = std::max<std::uint32_t>(children[i].weight, 1);
        centre += w * vec(children[i].centre);
        normal_sum += w * vec(children[i].normal);
        total += w;
        weight += children[i].weight;
    }
    centre /= total;
    // Opposite children (a thin wall, a whole closed surface) cancel: any normal then, and
    // the cone opens to the whole sphere below.
    const Eigen::Vector3d normal = normal_sum.norm() > 1e-6 * total ? normal_sum.normalized() : vec(children[0].normal);
    double radius = 0, cone = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
        radius = std::max(radius, (vec(children[i].centre) - centre).norm() + children[i].radius);
        cone = std::max(cone, angle_between(normal, vec(children[i].normal)) + children[i].cone);
    }
    BuildNode parent;
    parent.centre = floats(centre);
    parent.normal = floats(normal);
    // Float rounding of the centre must not uncover a child: round the radius up a little.
    parent.radius = static_cast<float>(radius * (1 + 1e-6) + 1e-6);
    parent.cone = static_cast<float>(std::min(cone * (1 + 1e-6) + 1e-6, kPi));
    parent.weight = static_cast<std::uint32_t>(std::min<std::uint64_t>(weight, UINT32_MAX));
    parent.origin = origin;
    parent.child_count = count;
    return parent;
}

void align_normals(BuildNode* children, std::uint32_t count) {
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (std::uint32_t i = 0; i < count; ++i) {
        const Eigen::Vector3d n = vec(children[i].normal);
        scatter += double(std::max<std::uint32_t>(children[i].weight, 1)) * n * n.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
    const Eigen::Vector3d principal = solver.eigenvectors().col(2);  // the largest eigenvalue's
    for (std::uint32_t i = 0; i < count; ++i)
        if (vec(children[i].normal).dot(principal) < 0)
            for (float& c : children[i].normal) c = -c;
}

bool coplanar_within(const BuildNode& parent, const BuildNode* children, std::uint32_t count, double tolerance) {
    if (tolerance <= 0) return false;
    const Eigen::Vector3d normal = vec(parent.normal), centre = vec(parent.centre);
    for (std::uint32_t i = 0; i < count; ++i) {
        if (children[i].child_count != 0) return false;
        // The offset alone beyond the tolerance decides it (the tilt's term is not negative),
        // without the angle's atan2 and sin.
        const double offset = std::abs(normal.dot(vec(children[i].centre) - centre));
        if (offset > tolerance) return false;
        const Eigen::Vector3d n = vec(children[i].normal);
        const double tilt = std::min(angle_between(normal, n), kPi / 2);
        const double deviation = offset + children[i].radius * std::sin(tilt);
        if (deviation > tolerance) return false;
    }
    return true;
}

}  // namespace vdbmesh::splat
