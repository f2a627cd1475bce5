#pragma once
/// @file grid.h
/// @brief Scans as sparse OpenVDB grids: streaming conversion, .vdb input and output.
/// This is the only public header (with mesher.h) that includes OpenVDB.

#include <openvdb/openvdb.h>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>

#include "vdbmesh/read.h"

namespace vdbmesh {

/// Options of convert_to_grid().
struct ConvertOptions {
    double iso = 0.0;                                    ///< isovalue (scaled sample units)
    std::optional<std::pair<double, double>> iso_range;  ///< keep every surface with an isovalue in [first, second]
    int band = 1;                                        ///< dilation of the active band, in voxels (>= 1)
    std::function<void(double)> progress;                ///< called with the fraction done (0..1), may be empty
};

/// Metadata keys written on converted grids.
inline constexpr const char* kMetaSourceFile = "vdbmesh_source_file";
inline constexpr const char* kMetaIsovalue = "vdbmesh_isovalue";
inline constexpr const char* kMetaUnits = "vdbmesh_units";
inline constexpr const char* kMetaValueMin = "vdbmesh_value_min";
inline constexpr const char* kMetaValueMax = "vdbmesh_value_max";
/// Index-space bounding box of the scanned samples (Vec3i min and max, inclusive). Outside
/// it lies no data: meshers treat it as outside the object (closing the surface there) or,
/// with --open-boundary, emit no triangles in cells that reach outside it.
inline constexpr const char* kMetaScanMin = "vdbmesh_scan_min";
inline constexpr const char* kMetaScanMax = "vdbmesh_scan_max";

/// Streams @a reader into a sparse float grid, a few slices at a time (TBB-parallel).
/// Active voxels: the corners of every cell whose samples straddle the isovalue (a value
/// above iso and one at or below it; or any value of iso_range), dilated by @a band voxels.
/// Inactive voxels and tiles hold values on the correct side of the isovalue; the
/// background is outside (below the isovalue). Voxel (i, j, k) holds sample (i, j, k);
/// the transform maps it to the world as the header's index_to_world does.
/// Memory: the sparse result plus a few slices. Throws FormatError on bad data.
openvdb::FloatGrid::Ptr convert_to_grid(VolumeReader& reader, const ConvertOptions& options);

/// Writes @a grid to @a path atomically (temporary file, then rename).
void write_vdb(const openvdb::FloatGrid& grid, const std::filesystem::path& path);

/// Reads the first float grid of a .vdb file; throws FormatError when there is none.
openvdb::FloatGrid::Ptr read_vdb(const std::filesystem::path& path);

/// The isovalue stored on a converted grid, if any.
std::optional<double> stored_isovalue(const openvdb::FloatGrid& grid);

}  // namespace vdbmesh
