#pragma once
// Private: a phantom's geometry with its rotation and centre worked out once, so that the
// signed distance can be evaluated per voxel without repeating the trigonometry.

#include <array>

#include "vdbmesh/phantom.h"

namespace vdbmesh::detail {

class PhantomField {
public:
    /// Validates @a spec (validate_phantom) and precomputes its frame.
    explicit PhantomField(const PhantomSpec& spec);

    /// Exact Euclidean signed distance to the surface, in voxels (negative inside).
    double signed_distance(double x, double y, double z) const;
    /// s(signed distance, blur).
    double density(double x, double y, double z) const;
    /// A point of the shape's own frame (centred at the origin, unrotated) in the volume's.
    std::array<double, 3> to_volume(const std::array<double, 3>& shape_point) const;

    const PhantomSpec& spec() const { return spec_; }

private:
    PhantomSpec spec_;
    std::array<double, 3> centre_;
    std::array<std::array<double, 3>, 3> rotation_;  ///< shape frame -> volume frame (Rz * Ry * Rx)
};

}  // namespace vdbmesh::detail
