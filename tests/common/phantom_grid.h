#pragma once
// Test helper: a phantom of include/vdbmesh/phantom.h as the pipeline sees a scan.

#include <openvdb/openvdb.h>

#include "vdbmesh/phantom.h"

namespace vdbmesh::test {

/// The phantom written as float samples (NIfTI, in a scratch folder) and converted like a
/// scan at its surface's isovalue 0.5.
openvdb::FloatGrid::Ptr phantom_scan_grid(const PhantomSpec& spec);

}  // namespace vdbmesh::test
