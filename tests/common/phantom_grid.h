#pragma once
// Test helper: a phantom of include/vdbmesh/phantom.h as the pipeline sees a scan.

#include <openvdb/openvdb.h>

#include <array>

#include "vdbmesh/phantom.h"

namespace vdbmesh::test {

/// The phantom written as float samples (NIfTI, in a scratch folder) and converted like a
/// scan at its surface's isovalue 0.5.
openvdb::FloatGrid::Ptr phantom_scan_grid(const PhantomSpec& spec);

/// A slightly tilted cylinder (56 x 56 x 600 samples, blurred over a voxel) through five node
/// layers along z: its wall crosses four node borders and its flat caps turn sharply, the case
/// the bricks' and ranks' tests split by layers.
inline PhantomSpec cylinder_through_five_nodes() {
    PhantomSpec spec;
    spec.shape = PhantomShape::cylinder;
    spec.dims = {56, 56, 600};
    spec.radius = 17;
    spec.height = 560;
    spec.rotation_degrees = {0.8, 0.5, 0};
    spec.blur = 1;
    return spec;
}

/// A sphere across the node border x = 128, its grid mirrored in x (a negative scale, as an
/// x-flipped scan's): the bricks' and ranks' tests of winding.
inline openvdb::FloatGrid::Ptr mirrored_sphere_across_a_node_border() {
    PhantomSpec spec;
    spec.dims = {150, 60, 60};
    spec.radius = 25;
    spec.centre = std::array<double, 3>{128.5, 30, 30};
    openvdb::FloatGrid::Ptr grid = phantom_scan_grid(spec);
    grid->transform().preScale(openvdb::Vec3d(-1, 1, 1));
    return grid;
}

}  // namespace vdbmesh::test
