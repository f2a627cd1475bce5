// Sample classification for the meshers: isovalue side and the scanned box (see grid.h).

#include "mesh/sample_classifier.h"

#include "vdbmesh/grid.h"

namespace vdbmesh::detail {

SampleClassifier::SampleClassifier(const openvdb::FloatGrid& grid, const MeshOptions& options)
    : iso_(options.iso), above_(options.inside == Inside::above), box_(stored_scan_box(grid)) {}

}  // namespace vdbmesh::detail
