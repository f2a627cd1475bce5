#pragma once
/// @file grid.h
/// @brief Scans as sparse OpenVDB grids: streaming conversion, .vdb input and output.
/// This is one of the two public headers that include OpenVDB (with trilinear_field.h);
/// mesher.h and compare.h take a grid by reference and only declare it (openvdb_fwd.h).

#include <openvdb/openvdb.h>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

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
/// With ConvertOptions::iso_range, the range (Vec2d) instead of kMetaIsovalue.
inline constexpr const char* kMetaIsoRange = "vdbmesh_iso_range";
/// Written by write_vdb(): a checksum (hex string) over the grid's tree, transform and other
/// vdbmesh_* metadata; reading a file whose grid carries it checks it.
inline constexpr const char* kMetaChecksum = "vdbmesh_checksum";

/// Streams @a source (a VolumeReader, or an array in memory) into a sparse float grid, a few slices at a time (TBB-parallel).
/// Active voxels: the corners of every cell whose samples straddle the isovalue (a value
/// above iso and one at or below it; or any value of iso_range), dilated by @a band voxels.
/// Samples outside the scan count as outside, so the band closes where the object touches
/// the scan's border (active voxels reach band + 1 voxels beyond it, holding the background).
/// Inactive voxels in leaves keep their sample; inactive tiles hold the minimum sample of
/// their 8^3 block (on the block's side of every isovalue); everything else is background:
/// min(data minimum, lowest isovalue) minus 1% of the value range, so strictly below every
/// isovalue and every sample. Voxel (i, j, k) holds sample (i, j, k); the transform maps it to
/// the world as the header's index_to_world does. Grid "density", class unknown (not a level
/// set), with the kMeta* metadata above. Same grid for any thread count.
/// Memory: the sparse result plus 2 * band + 18 slices of floats and 4 * band + 17 of bytes. Throws FormatError on bad data, UsageError
/// on bad options (band outside 1..32, iso_range reversed, an isovalue outside the float range).
openvdb::FloatGrid::Ptr convert_to_grid(SliceReader& source, const ConvertOptions& options);

/// Writes @a grid to @a path atomically (temporary file, then rename).
void write_vdb(const openvdb::FloatGrid& grid, const std::filesystem::path& path);

/// Reads the first float grid of a .vdb file; throws FormatError when there is none.
openvdb::FloatGrid::Ptr read_vdb(const std::filesystem::path& path);

/// The isovalue stored on a converted grid, if any.
std::optional<double> stored_isovalue(const openvdb::FloatGrid& grid);

/// The isovalues a converted grid's active band was built for: [iso, iso] (kMetaIsovalue) or
/// the stored kMetaIsoRange; none when the grid records neither. At any other isovalue the
/// surface may cross cells that the band left out, so meshing there gives a wrong surface.
std::optional<std::pair<double, double>> band_isovalues(const openvdb::FloatGrid& grid);

/// The scanned box stored on a converted grid (kMetaScanMin/Max, index space, inclusive), if any.
std::optional<openvdb::CoordBBox> stored_scan_box(const openvdb::FloatGrid& grid);

/// What `vdbmesh info` reports about one grid of a .vdb file.
struct GridInfo {
    std::string name, grid_class, value_type;  ///< e.g. "density", "unknown", "float"
    openvdb::Index64 active_voxels = 0;         ///< voxels plus voxels of active tiles
    openvdb::Index64 leaf_nodes = 0;
    openvdb::Index64 memory_bytes = 0;          ///< in memory, as Tree::memUsage() counts it
    openvdb::CoordBBox index_bbox;              ///< of the active values, inclusive; empty when none
    openvdb::BBoxd world_bbox;                  ///< index_bbox's corners through the transform
    openvdb::Vec3d voxel_size{1, 1, 1};
    std::optional<std::pair<double, double>> value_range;  ///< min, max of active values (float grids)
    std::optional<double> isovalue;  ///< stored by convert_to_grid, or 0 for a level set
    std::vector<std::pair<std::string, std::string>> metadata;  ///< name, value as text
};

/// Describes one grid.
GridInfo describe_grid(const openvdb::GridBase& grid);
/// Describes every grid of a .vdb file; throws FormatError when it cannot be read.
std::vector<GridInfo> describe_vdb_file(const std::filesystem::path& path);

}  // namespace vdbmesh
