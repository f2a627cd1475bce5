#pragma once
// The input of the grid-consuming subcommands (mesh, compare): a .vdb read as stored, or a
// scan (with the further parts of a split raw scan) converted to a grid on the fly.

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common_options.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/read.h"

namespace vdbmesh::cli {

/// The extension of @a path ("" if none) in lower case, with its dot: ".vdb".
std::string lowercase_extension(const std::string& path);

/// True when @a path names a mesh file (.stl, .ply, .obj).
bool is_mesh_file(const std::string& path);

/// Opens inputs.front() as a scan; the further inputs are the next parts of a split raw scan.
std::unique_ptr<VolumeReader> open_scan(const std::vector<std::string>& inputs, const ReadFlags& read);

/// A grid and the isovalue and side it is to be meshed at.
struct GridInput {
    openvdb::FloatGrid::Ptr grid;
    double iso = 0;                 ///< minus the one asked for a scan converted negated (convert_for_side())
    Inside inside = Inside::above;  ///< above for a scan converted negated
    std::optional<double> convert_seconds;  ///< none for a .vdb input
    bool level_set = false;                 ///< a .vdb level set: iso 0 by default, inside below
};

/// A .vdb (lowercase_extension()) as stored, at @a iso or else its stored isovalue (0 for a
/// level set), the object on @a inside (default: below for a level set, else above); or a scan
/// converted with @a convert at @a iso (required) for the object on @a inside (default above),
/// closed at its box either side (convert_for_side()). @a purpose ("mesh", "compare on")
/// completes the UsageError text when @a iso_option (the option giving @a iso: "--iso",
/// "--clip-iso") is missing. Throws Error when @a iso lies outside the isovalues a .vdb's band
/// was built for (band_isovalues()); UsageError for a mesh file (is_mesh_file()).
GridInput load_grid(const std::vector<std::string>& inputs, std::optional<double> iso, const ReadFlags& read,
                    const std::string& purpose, ConvertOptions convert, const std::string& iso_option = "--iso",
                    std::optional<Inside> inside = std::nullopt);

/// A grid read by region (grid_region.h) and the isovalue it is to be meshed at.
struct GridRegionsInput {
    std::unique_ptr<GridRegionSource> source;
    double iso = 0;
    Inside inside = Inside::above;  ///< as load_grid() chooses it (a scan's samples are never negated here)
};

/// load_grid()'s input by region, never whole: a .vdb's topology (open_vdb_regions()), or a scan
/// surveyed and read in z-bands (open_scan_regions()). The same checks and errors as load_grid().
GridRegionsInput open_grid_regions(const std::vector<std::string>& inputs, std::optional<double> iso, const ReadFlags& read,
                                   const std::string& purpose, ConvertOptions convert, const std::string& iso_option = "--iso",
                                   std::optional<Inside> inside = std::nullopt);

/// The error for a grid of @a input with no surface at @a isovalues (low, high; equal for one
/// isovalue) outside the values or in a constant volume: it names the stored value range when
/// known (both in the scan's terms for a grid of negated samples), and says @a output was not
/// written (when not empty). When @a grid_steps (grid_steps_text()) removed a surface that the
/// stored values have at the isovalue, it blames them, not the isovalue.
Error no_surface_error(const std::string& input, const openvdb::FloatGrid& grid, std::pair<double, double> isovalues,
                       const std::string& output, const std::string& grid_steps = "");

/// convert_for_side() for the object on @a inside, timed into @a seconds.
openvdb::FloatGrid::Ptr convert_timed(VolumeReader& reader, const ConvertOptions& convert,
                                      std::optional<double>& seconds, Inside inside = Inside::above);

}  // namespace vdbmesh::cli
