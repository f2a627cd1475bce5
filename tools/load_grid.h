#pragma once
// The input of the grid-consuming subcommands (mesh, compare): a .vdb read as stored, or a
// scan (with the further parts of a split raw scan) converted to a grid on the fly.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common_options.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/read.h"

namespace vdbmesh::cli {

/// The extension of @a path ("" if none) in lower case, with its dot: ".vdb".
std::string lowercase_extension(const std::string& path);

/// Opens inputs.front() as a scan; the further inputs are the next parts of a split raw scan.
std::unique_ptr<VolumeReader> open_scan(const std::vector<std::string>& inputs, const ReadFlags& read);

/// A grid and the isovalue it is to be meshed at.
struct GridInput {
    openvdb::FloatGrid::Ptr grid;
    double iso = 0;
    std::optional<double> convert_seconds;  ///< none for a .vdb input
};

/// A .vdb (lowercase_extension()) as stored, at @a iso or else its stored isovalue; or a
/// scan converted with @a convert at @a iso (required). @a purpose ("mesh", "compare on")
/// completes the UsageError text when --iso is missing.
GridInput load_grid(const std::vector<std::string>& inputs, std::optional<double> iso, const ReadFlags& read,
                    const std::string& purpose, ConvertOptions convert);

/// convert_to_grid(), timed into @a seconds.
openvdb::FloatGrid::Ptr convert_timed(VolumeReader& reader, const ConvertOptions& convert,
                                      std::optional<double>& seconds);

}  // namespace vdbmesh::cli
