#pragma once
// The processing options of `vdbmesh mesh`: grid filters before meshing (grid_filter.h) and
// mesh processing after it (process.h), in a fixed order:
// --slab, --smooth, --step, --keep-largest/--min-component-volume, mesh, --taubin, --decimate/--max-error.

#include <nlohmann/json.hpp>

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "vdbmesh/grid.h"
#include "vdbmesh/grid_filter.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/process.h"

namespace vdbmesh::cli {

struct ProcessingOptions {
    std::string slab;  ///< [AXIS=]FIRST:LAST, z by default
    double smooth = 0;  ///< filter radius in voxels (rounded to whole voxels), 0: none
    SmoothFilter smooth_filter = SmoothFilter::gaussian;
    int step = 1;
    SolidSelection solids;
    int taubin = 0;
    std::optional<double> decimate;   ///< share of triangles kept
    std::optional<double> max_error;  ///< world units
};

/// Adds the grid and mesh processing options; returns them (all mean something for one surface only).
std::vector<const CLI::Option*> add_processing_options(CLI::App& command, ProcessingOptions& options);

/// The band to convert a scan with so that the filters read true samples (at least 1).
int conversion_band(const ProcessingOptions& options);

/// What the processing did, for the report.
struct ProcessingReport {
    SolidSelectionReport solids;
    TaubinReport taubin;
    DecimateReport decimate;
    std::size_t triangles_meshed = 0;  ///< before the mesh processing
};

/// --slab, --smooth, --step and the solid selection, in that order; @a grid may be replaced.
void process_grid(openvdb::FloatGrid::Ptr& grid, const MeshOptions& mesh, const ProcessingOptions& options,
                  ProcessingReport& report);

/// The grid steps given ("--slab 40:80, --step 4"), "" when none: what a missing surface may be
/// owed to besides the isovalue.
std::string grid_steps_text(const ProcessingOptions& options);

/// --taubin, then --decimate / --max-error.
Mesh process_mesh(Mesh mesh, const ProcessingOptions& options, ProcessingReport& report);

/// The settings and what they did (null where an option was not given).
nlohmann::ordered_json processing_json(const ProcessingOptions& options, const ProcessingReport& report);

}  // namespace vdbmesh::cli
