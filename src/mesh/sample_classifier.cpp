// Sample classification for the meshers: isovalue side and the scanned box (see grid.h).

#include "mesh/sample_classifier.h"

#include "vdbmesh/grid.h"

namespace vdbmesh::detail {

namespace {

std::optional<openvdb::CoordBBox> read_scan_box(const openvdb::FloatGrid& grid) {
    const auto min = grid.getMetadata<openvdb::Vec3IMetadata>(kMetaScanMin);
    const auto max = grid.getMetadata<openvdb::Vec3IMetadata>(kMetaScanMax);
    if (!min || !max) return std::nullopt;
    return openvdb::CoordBBox(openvdb::Coord(min->value()), openvdb::Coord(max->value()));
}

}  // namespace

SampleClassifier::SampleClassifier(const openvdb::FloatGrid& grid, const MeshOptions& options)
    : iso_(options.iso), above_(options.inside == Inside::above), box_(read_scan_box(grid)) {}

}  // namespace vdbmesh::detail
