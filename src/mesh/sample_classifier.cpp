// Sample classification for the meshers: isovalue side and the scanned box (see grid.h).

#include "mesh/sample_classifier.h"

#include <cmath>
#include <limits>

#include "vdbmesh/grid.h"

namespace vdbmesh::detail {

namespace {

/// The float nearest @a iso strictly above it (@a above) or strictly below it: the isovalue
/// lies between two neighbouring floats, or is one.
float first_float_beyond(double iso, bool above) {
    const float nearest = float(iso);
    if (above) return double(nearest) > iso ? nearest : std::nextafter(nearest, std::numeric_limits<float>::infinity());
    return double(nearest) < iso ? nearest : std::nextafter(nearest, -std::numeric_limits<float>::infinity());
}

}  // namespace

SampleClassifier::SampleClassifier(const openvdb::FloatGrid& grid, const MeshOptions& options)
    : iso_(options.iso), above_(options.inside == Inside::above), first_inside_(first_float_beyond(iso_, above_)), box_(stored_scan_box(grid)) {}

}  // namespace vdbmesh::detail
