#pragma once
// Private: writing the scanned box of a grid (kMetaScanMin/Max, read by stored_scan_box()).

#include <openvdb/openvdb.h>

#include "vdbmesh/grid.h"

namespace vdbmesh::detail {

inline void store_scan_box(openvdb::FloatGrid& grid, const openvdb::CoordBBox& box) {
    grid.insertMeta(kMetaScanMin, openvdb::Vec3IMetadata(box.min().asVec3i()));
    grid.insertMeta(kMetaScanMax, openvdb::Vec3IMetadata(box.max().asVec3i()));
}

}  // namespace vdbmesh::detail
