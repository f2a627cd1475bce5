// The processing options of `vdbmesh mesh` (see mesh_processing.h).

#include "mesh_processing.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

#include "common_options.h"
#include "vdbmesh/error.h"

namespace vdbmesh::cli {

namespace {

const std::map<std::string, SmoothFilter> kFilters = {
    {"gaussian", SmoothFilter::gaussian}, {"mean", SmoothFilter::mean}, {"median", SmoothFilter::median}};

struct Slab {
    int axis = 2, first = 0, last = 0;
};

/// "[AXIS=]FIRST:LAST" in slice indices.
Slab parse_slab(const std::string& text) {
    Slab slab;
    std::string range = text;
    const std::size_t equals = text.find('=');
    const auto fail = [&] { throw UsageError("--slab: expected [AXIS=]FIRST:LAST in slices, e.g. 40:80 or x=10:20, got \"" + text + "\""); };
    if (equals != std::string::npos) {
        const std::string axis = text.substr(0, equals);
        if (axis.size() != 1 || std::string("xyzXYZ").find(axis[0]) == std::string::npos) fail();
        slab.axis = std::tolower(axis[0]) - 'x';
        range = text.substr(equals + 1);
    }
    std::replace(range.begin(), range.end(), ':', ',');
    std::vector<double> bounds;
    try {
        bounds = parse_number_list("--slab", range);
    } catch (const UsageError&) {
        fail();
    }
    if (bounds.size() != 2 || bounds[0] != std::floor(bounds[0]) || bounds[1] != std::floor(bounds[1]) || bounds[0] > bounds[1] ||
        std::abs(bounds[0]) > 1e9 || std::abs(bounds[1]) > 1e9)
        fail();
    slab.first = int(bounds[0]);
    slab.last = int(bounds[1]);
    return slab;
}

}  // namespace

std::vector<const CLI::Option*> add_processing_options(CLI::App& command, ProcessingOptions& options) {
    auto* grid = command.add_option_group("Grid processing (before meshing)");
    grid->add_option("--slab", options.slab, "Only slices [AXIS=]FIRST:LAST (z by default), closed at the cut");
    grid->add_option("--smooth", options.smooth, "Smooth the samples first: filter radius in voxels, rounded to whole voxels (OpenVDB filter)")
        ->check(CLI::Range(0.5, 7.0));  // the Gaussian reads 4 R + 1 voxels away; a scan band is at most 32
    grid->add_option("--smooth-filter", options.smooth_filter, "Filter of --smooth: gaussian|mean|median")
        ->transform(CLI::CheckedTransformer(kFilters, CLI::ignore_case));
    grid->add_option("--step", options.step, "Sample every N-th voxel along each axis")->check(CLI::Range(1, 64));
    grid->add_flag("--keep-largest", options.solids.keep_largest, "Keep only the largest solid (face-connected inside samples)");
    grid->add_option("--min-component-volume", options.solids.min_volume, "Drop solids smaller than this (world units^3)")
        ->check(kFiniteNonNegative);
    auto* mesh = command.add_option_group("Mesh processing (after meshing)");
    mesh->add_option("--taubin", options.taubin, "Taubin lambda/mu smoothing iterations (never self-intersecting)")
        ->check(CLI::Range(0, 1000));
    mesh->add_option("--decimate", options.decimate, "Keep this share of the triangles, in (0, 1] (quadric edge collapse)")
        ->check(kFinitePositive & CLI::Range(0.0, 1.0));
    mesh->add_option("--max-error", options.max_error, "Decimate while the quadric error stays under this (world units)")
        ->check(kFiniteNonNegative);
    std::vector<const CLI::Option*> added;
    for (const CLI::App* group : {grid, mesh})
        for (const CLI::Option* option : group->get_options()) added.push_back(option);
    return added;
}

namespace {
int filter_radius(const ProcessingOptions& options) { return int(std::lround(options.smooth)); }
}  // namespace

int conversion_band(const ProcessingOptions& options) {
    return options.smooth > 0 ? smoothing_reach(filter_radius(options), options.smooth_filter) + 1 : 1;
}

void process_grid(openvdb::FloatGrid::Ptr& grid, const MeshOptions& mesh, const ProcessingOptions& options,
                  ProcessingReport& report) {
    if (!options.slab.empty()) {
        const Slab slab = parse_slab(options.slab);
        restrict_to_slab(*grid, slab.axis, slab.first, slab.last);
    }
    if (options.smooth > 0) smooth_grid(*grid, filter_radius(options), options.smooth_filter);
    if (options.step > 1) grid = subsample_grid(*grid, options.step);
    if (options.solids.keep_largest || options.solids.min_volume > 0) report.solids = select_solids(*grid, mesh, options.solids);
}

std::string grid_steps_text(const ProcessingOptions& options) {
    std::vector<std::string> steps;
    if (!options.slab.empty()) steps.push_back("--slab " + options.slab);
    if (options.smooth > 0) steps.push_back("--smooth " + std::to_string(filter_radius(options)));
    if (options.step > 1) steps.push_back("--step " + std::to_string(options.step));
    if (options.solids.keep_largest) steps.push_back("--keep-largest");
    if (options.solids.min_volume > 0) steps.push_back("--min-component-volume");
    std::string text;
    for (const std::string& step : steps) text += (text.empty() ? "" : ", ") + step;
    return text;
}

Mesh process_mesh(Mesh mesh, const ProcessingOptions& options, ProcessingReport& report) {
    report.triangles_meshed = mesh.triangles.size();
    if (options.taubin > 0) {
        TaubinOptions taubin;
        taubin.iterations = options.taubin;
        mesh = taubin_smooth(mesh, taubin, &report.taubin);
    }
    if (options.decimate || options.max_error) {
        DecimateOptions decimate;
        if (options.decimate) decimate.keep_fraction = *options.decimate;
        if (options.max_error) decimate.max_error = *options.max_error;
        mesh = decimate_mesh(mesh, decimate, &report.decimate);
    }
    return mesh;
}

nlohmann::ordered_json processing_json(const ProcessingOptions& o, const ProcessingReport& r) {
    const auto optional = [](bool given, const nlohmann::ordered_json& value) { return given ? value : nlohmann::ordered_json(nullptr); };
    std::string filter;
    for (const auto& [name, value] : kFilters) {
        if (value == o.smooth_filter) filter = name;
    }
    nlohmann::ordered_json j;
    j["slab"] = optional(!o.slab.empty(), o.slab);
    j["smooth"] = optional(o.smooth > 0, {{"radius", filter_radius(o)}, {"filter", filter}});
    j["step"] = o.step;
    const bool select = o.solids.keep_largest || o.solids.min_volume > 0;
    j["solids"] = optional(select, {{"keep_largest", o.solids.keep_largest}, {"min_volume", o.solids.min_volume},
                                    {"found", r.solids.solids}, {"dropped", r.solids.dropped}});
    j["triangles_meshed"] = r.triangles_meshed;
    j["taubin"] = optional(o.taubin > 0, {{"iterations", o.taubin}, {"held_back", r.taubin.held_back}});
    const bool decimated = o.decimate || o.max_error;
    j["decimate"] = optional(decimated, {{"keep_fraction", o.decimate ? nlohmann::ordered_json(*o.decimate) : nullptr},
                                         {"max_error", o.max_error ? nlohmann::ordered_json(*o.max_error) : nullptr},
                                         {"collapses", r.decimate.collapses},
                                         {"error_bound", r.decimate.max_error},
                                         {"rejected_topology", r.decimate.rejected_topology},
                                         {"rejected_geometry", r.decimate.rejected_geometry},
                                         {"rejected_intersection", r.decimate.rejected_intersection}});
    return j;
}

}  // namespace vdbmesh::cli
