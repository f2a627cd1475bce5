// `vdbmesh compare IN [--iso V] [--error LIST] [--adaptivity LIST] [--no-budget] [--sharp] [--decimate LIST] [--json FILE] [--plot FILE.svg]`
// `vdbmesh compare --phantom SHAPE [--size N] [--blur W] ...`
// Converts once, then meshes the same grid in this process with DC (the default mesher) at each
// --error, Marching Cubes, volumeToMesh at each --adaptivity, the triangle budget at each
// volumeToMesh mesh's count (as `vdbmesh mesh --triangles`; not with --no-budget), DC --sharp at
// each --error above 0 (on a phantom, or with --sharp), and DC at
// error 0 decimated to each --decimate fraction (as `vdbmesh mesh --decimate`), and measures each mesh (compare_meshers(),
// include/vdbmesh/compare.h): time, `vdbmesh check`'s figures, two-sided distance to the true
// isosurface in voxels and normal deviation. The true surface of a scan or .vdb is the
// trilinear isosurface of its grid; of a phantom (written to a temporary float NIfTI, then
// converted like any scan), the exact analytic surface.

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "cli.h"
#include "commands.h"
#include "common_options.h"
#include "load_grid.h"
#include "option_checks.h"
#include "report_json.h"
#include "svg_plot.h"
#include "work_limits.h"
#include "write_text_file.h"
#include "vdbmesh/compare.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/phantom.h"
#include "vdbmesh/write_volume.h"

namespace vdbmesh::cli {
namespace {

struct CompareCommandOptions {
    std::vector<std::string> inputs;
    std::optional<double> iso;
    std::string phantom;
    std::int64_t size = 64;
    double blur = 5;
    std::string errors = "0,0.1,0.25,0.5", adaptivities = "0,0.1,0.25,1";
    std::string decimate;
    bool no_budget = false;
    bool no_dual = false;  ///< --no-dual: no dual-surface row at adaptivity 0
    bool sharp = false;  ///< --sharp: DC --sharp rows at each positive --error (always on a phantom)
    std::optional<std::string> dmc_errors;  ///< refused: DMC was retired (docs/dmc.md)
    Inside inside = Inside::above;
    std::size_t samples = 100000;
    std::string json, plot;
    ReadFlags read;
    CommonOptions common;
    WorkLimit work_limit;
    MemoryLimit memory;
};

/// The grid to compare on, and what the report says about where it came from.
struct LoadedGrid : GridInput {
    std::optional<PhantomSpec> phantom;
};

/// A fresh folder under the system temp dir, removed on destruction.
class TempFolder {
public:
    TempFolder() {
        static int counter = 0;
        path_ = std::filesystem::temp_directory_path() /
                ("vdbmesh-compare-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        std::filesystem::create_directories(path_);
    }
    ~TempFolder() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

ConvertOptions convert_with_progress(Progress& progress) {
    ConvertOptions convert;
    convert.progress = [&](double f) { progress(f); };
    return convert;
}

/// The phantom written as float samples (density 0..1, surface at 0.5), then converted.
LoadedGrid load_phantom(const CompareCommandOptions& o) {
    if (!o.inputs.empty()) throw UsageError("--phantom: takes no input file");
    o.read.refuse_for("--phantom");
    LoadedGrid loaded;
    PhantomSpec spec = phantom_preset(o.phantom, {o.size, o.size, o.size});
    spec.blur = o.blur;
    validate_phantom(spec);
    refuse_beyond_memory("--size", "the phantom's float samples, written to a temporary file", 4.0 * std::pow(double(o.size), 3));
    loaded.phantom = spec;
    loaded.iso = o.iso.value_or(0.5);
    loaded.inside = o.inside;
    const TempFolder folder;
    VolumeHeader header;
    header.dims = spec.dims;
    header.type = SampleType::f32;
    header.index_to_world = axis_aligned_affine({1, 1, 1});
    const std::filesystem::path file = folder.path() / "phantom.nii";
    write_volume(file, header, [&](std::int64_t z, float* slice) { fill_phantom_slice(spec, z, slice); });
    auto reader = open_volume(file);
    Progress progress("converting", o.common.quiet);
    ConvertOptions convert = convert_with_progress(progress);
    convert.iso = loaded.iso;
    loaded.grid = convert_timed(*reader, convert, loaded.convert_seconds);
    return loaded;
}

LoadedGrid load_input(const CompareCommandOptions& o) {
    if (!o.phantom.empty()) return load_phantom(o);
    if (o.inputs.empty()) throw UsageError("compare: needs an input file or --phantom SHAPE");
    Progress progress("converting", o.common.quiet);
    LoadedGrid loaded;
    static_cast<GridInput&>(loaded) = load_grid(o.inputs, o.iso, o.read, "compare on", convert_with_progress(progress), "--iso", o.inside);
    return loaded;
}

nlohmann::ordered_json grid_json(const CompareCommandOptions& o, const LoadedGrid& loaded, std::size_t reference) {
    nlohmann::ordered_json j;
    j["input"] = loaded.phantom ? "phantom:" + o.phantom : o.inputs.front();
    j["isovalue"] = o.iso.value_or(loaded.iso);  // as asked: loaded.iso is its negative for a scan's object below
    j["inside"] = o.inside == Inside::above ? "above" : "below";
    j["truth"] = loaded.phantom ? "exact phantom surface" : "trilinear isosurface";
    if (loaded.phantom) {
        j["phantom_size"] = o.size;
        j["phantom_blur"] = o.blur;
    }
    j["convert_seconds"] = loaded.convert_seconds ? nlohmann::ordered_json(*loaded.convert_seconds) : nullptr;
    j["active_voxels"] = loaded.grid->activeVoxelCount();
    j["leaf_nodes"] = loaded.grid->tree().leafCount();
    const openvdb::Vec3d voxel = loaded.grid->voxelSize();
    j["voxel_size"] = {voxel[0], voxel[1], voxel[2]};
    j["samples"] = o.samples;
    // (a phantom's reference points are drawn on its exact surface, corners and edges included)
    j["reference_triangles"] = loaded.phantom ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(reference);
    return j;
}

nlohmann::ordered_json mesh_json(const MeshComparison& m) {
    nlohmann::ordered_json j;
    j["method"] = method_name(m.method);
    j["error"] = m.error ? nlohmann::ordered_json(*m.error) : nullptr;
    j["sharp"] = m.sharp;
    j["adaptivity"] = m.adaptivity ? nlohmann::ordered_json(*m.adaptivity) : nullptr;
    j["decimate"] = m.decimate ? nlohmann::ordered_json(*m.decimate) : nullptr;
    j["triangle_budget"] = m.budget ? nlohmann::ordered_json(*m.budget) : nullptr;
    j["seconds"] = m.seconds;
    j["decimate_seconds"] = m.decimate ? nlohmann::ordered_json(m.decimate_seconds) : nullptr;
    j["phases"] = phases_json(m.mesher);
    j["same_mesh_as"] = m.same_mesh_as ? nlohmann::ordered_json(*m.same_mesh_as) : nullptr;
    const DistanceReport& d = m.accuracy.distance;
    j["hausdorff_voxels"] = d.hausdorff;
    j["mean_distance_voxels"] = d.mean;
    j["rms_distance_voxels"] = d.rms;
    j["max_to_surface_voxels"] = d.max_a_to_b;
    j["max_from_surface_voxels"] = d.max_b_to_a;
    j["mean_to_surface_voxels"] = d.mean_a_to_b;
    j["mean_from_surface_voxels"] = d.mean_b_to_a;
    j["unresolved_samples"] = m.accuracy.unresolved_samples;
    j["normal_mean_deg"] = m.accuracy.normals.mean_deg;
    j["normal_p95_deg"] = m.accuracy.normals.p95_deg;
    j["manifold"] = m.analysis.nonmanifold_edges == 0 && m.analysis.nonmanifold_vertices == 0;
    j.update(report_json(m.analysis));
    return j;
}

/// The setting of @a m: each value after its name in @a names (decimate, error, adaptivity,
/// triangle budget, error with --sharp).
std::string setting_text(const MeshComparison& m, const std::array<const char*, 5>& names) {
    std::ostringstream text;
    if (m.budget)
        text << names[3] << *m.budget;
    else if (m.decimate)
        text << names[0] << *m.decimate;
    else if (m.error)
        text << names[m.sharp ? 4 : 1] << *m.error;
    if (m.adaptivity) text << names[2] << *m.adaptivity;
    return text.str();
}

void print_table(const nlohmann::ordered_json& report, const std::vector<MeshComparison>& meshes, std::ostream& out) {
    const auto& g = report["grid"];
    out << g["input"].get<std::string>() << ": iso " << g["isovalue"] << ", " << g["active_voxels"]
        << " active voxels, truth: " << g["truth"].get<std::string>();
    if (!g["convert_seconds"].is_null()) out << ", converted in " << g["convert_seconds"].get<double>() << " s";
    out << "\n";
    out << std::left << std::setw(9) << "method" << std::setw(12) << "setting" << std::right << std::setw(9) << "seconds"
        << std::setw(11) << "triangles" << std::setw(11) << "vertices" << std::setw(11) << "hausdorff" << std::setw(9)
        << "mean" << std::setw(9) << "n.mean" << std::setw(8) << "n.p95" << std::setw(8) << "<10deg" << std::setw(8) << "selfX" << std::setw(8)
        << "closed" << std::setw(10) << "manifold" << std::setw(7) << "clean" << "\n";
    out << std::fixed;
    for (const auto& m : meshes) {
        const DistanceReport& d = m.accuracy.distance;
        out << std::left << std::setw(9) << method_name(m.method) << std::setw(12) << setting_text(m, {"dec ", "error ", "adapt ", "<= ", "sharp "}) << std::right
            << std::setprecision(3) << std::setw(9) << m.seconds << std::setw(11) << m.analysis.triangles << std::setw(11)
            << m.analysis.vertices << std::setprecision(4) << std::setw(11) << d.hausdorff << std::setw(9) << d.mean
            << std::setprecision(2) << std::setw(9) << m.accuracy.normals.mean_deg << std::setw(8)
            << m.accuracy.normals.p95_deg << std::setw(7) << 100 * m.analysis.small_angle_share << "%"
            << std::setw(8) << m.analysis.self_intersecting_pairs << std::setw(8)
            << (m.analysis.closed ? "yes" : "no") << std::setw(10)
            << (m.analysis.nonmanifold_edges == 0 && m.analysis.nonmanifold_vertices == 0 ? "yes" : "no") << std::setw(7)
            << (m.analysis.is_clean() ? "yes" : "no") << "\n";
    }
    out << std::defaultfloat << "distances in voxels (two-sided, " << g["samples"]
        << " samples each way); normal deviation in degrees; <10deg: the share of angles under 10 degrees\n";
}

/// "dc error 0.25", "openvdb adapt 1", ...: a row as the table names it.
std::string row_name(const MeshComparison& m) {
    const std::string setting = setting_text(m, {"dec ", "error ", "adapt ", "<= ", "sharp "});
    return std::string(method_name(m.method)) + (setting.empty() ? "" : " " + setting);
}

std::string row_names(const std::vector<MeshComparison>& meshes, const std::vector<std::size_t>& rows) {
    std::string text;
    for (const std::size_t i : rows) text += (text.empty() ? "" : ", ") + row_name(meshes[i]);
    return text.empty() ? "none" : text;
}

/// Under the table: for each volumeToMesh row, the rows of ours that beat it on every count, and
/// on time too (issue 29, item 5: the plain command shows the dominance).
void print_dominance(const std::vector<Dominance>& dominance, const std::vector<MeshComparison>& meshes, std::ostream& out) {
    if (dominance.empty()) return;
    out << "beaten on every count (no more triangles, no larger Hausdorff, no more angles under 10 degrees, clean)"
        << " and no slower (at adaptivity 1: " << kAdaptivityOneTimeFactor << "x its time) by:\n";
    for (const Dominance& d : dominance) {
        out << "  " << row_name(meshes[d.volume_to_mesh]) << ": " << row_names(meshes, d.with_time);
        if (d.every_count.size() > d.with_time.size()) out << "; ignoring time: " << row_names(meshes, d.every_count);
        if (d.closest) {
            std::string lost;
            for (const char* count : d.closest_loses) lost += (lost.empty() ? "" : ", ") + std::string(count);
            out << " (closest: " << row_name(meshes[*d.closest]) << ", loses on " << lost << ")";
        }
        out << "\n";
    }
}

nlohmann::ordered_json dominance_json(const std::vector<Dominance>& dominance) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const Dominance& d : dominance) {
        nlohmann::ordered_json j;
        j["volume_to_mesh"] = d.volume_to_mesh;
        j["every_count"] = d.every_count;
        j["with_time"] = d.with_time;
        j["closest"] = d.closest ? nlohmann::ordered_json(*d.closest) : nullptr;
        j["closest_loses"] = nlohmann::ordered_json::array();
        for (const char* count : d.closest_loses) j["closest_loses"].push_back(count);
        list.push_back(j);
    }
    return list;
}

Plot make_plot(const std::string& title, const std::vector<MeshComparison>& meshes) {
    Plot plot;
    plot.title = title;
    plot.x_label = "triangles (log scale)";
    plot.y_label = "two-sided Hausdorff distance (voxels)";
    for (MeshMethod method : {MeshMethod::dc, MeshMethod::mc, MeshMethod::dual, MeshMethod::openvdb}) {
        for (const char* kind : {"", " + decimate", " budget", " sharp"}) {
            PlotSeries series;
            series.name = method == MeshMethod::openvdb ? "volumeToMesh"
                          : method == MeshMethod::dc   ? "DC"
                          : method == MeshMethod::dual ? "dual surface"
                                                       : "MC";
            series.name += kind;
            for (const auto& m : meshes) {
                const char* of = m.budget ? " budget" : m.decimate ? " + decimate" : m.sharp ? " sharp" : "";
                if (m.method != method || std::string(of) != kind) continue;
                series.points.push_back({double(m.analysis.triangles), m.accuracy.distance.hausdorff, setting_text(m, {"d=", "e=", "a=", "<=", "s="})});
            }
            if (!series.points.empty()) plot.series.push_back(series);
        }
    }
    return plot;
}

/// --memory, once the grid is made and before any mesh: the meshers need the whole grid, so the
/// need is the grid, the meshing at its peak and the surface samples of both sides. Meshing
/// peaks at about 150 bytes a triangle (issue 28's table), 180 here as compare keeps a few
/// meshes (the bunny k = 1 .vdb at --error 0.25 --adaptivity 0.25: 664 MB, estimated 650); the
/// densest mesh, Marching Cubes', has about 0.65 triangles an active voxel of a band-1 grid
/// (the bunny's 3.02 M for 4.64 M).
void refuse_beyond_grid_estimate(const CompareCommandOptions& o, const openvdb::FloatGrid& grid) {
    const double triangles = 0.65 * double(grid.activeVoxelCount());
    refuse_beyond_memory(o.memory, "--memory", "the grid and its meshes (volumeToMesh and the others need the whole grid)",
                         double(grid.memUsage()) + 180 * triangles + 2 * 24.0 * double(o.samples));
}

int run_compare(const CompareCommandOptions& o) {
    const ThreadLimit limit(o.common);
    CompareOptions options;
    if (!o.plot.empty() && std::filesystem::path(o.plot).extension() != ".svg")
        throw UsageError("--plot: expected a file name ending in .svg (the chart is SVG), got \"" + o.plot + "\"");
    options.errors = parse_number_list("--error", o.errors);
    if (o.dmc_errors)
        throw UsageError("--dmc-error: dmc was retired (docs/dmc.md); give dc's error tolerances with --error, got \"" + *o.dmc_errors + "\"");
    options.adaptivities = parse_number_list("--adaptivity", o.adaptivities);
    const auto require_each = [](const std::string& flag, const std::vector<double>& values, double high, const char* expected) {
        for (const double v : values) {
            if (v >= 0 && v <= high) continue;
            std::ostringstream got;
            got << v;
            throw UsageError(flag + ": expected " + expected + ", got " + got.str());
        }
    };
    require_each("--error", options.errors, HUGE_VAL, "tolerances >= 0");
    require_each("--adaptivity", options.adaptivities, 1, "adaptivities in [0, 1]");
    if (!o.decimate.empty()) options.decimate_fractions = parse_number_list("--decimate", o.decimate);
    for (const double f : options.decimate_fractions) {
        if (!(f > 0 && f <= 1)) {
            std::ostringstream got;
            got << f;
            throw UsageError("--decimate: expected shares of triangles to keep in (0, 1], got " + got.str());
        }
    }
    options.accuracy.samples = o.samples;
    options.budget_rows = !o.no_budget;
    // The row meant to meet volumeToMesh at 0 (issue 29, item 5), as the budget rows meet the others.
    options.dual = !o.no_dual && std::count(options.adaptivities.begin(), options.adaptivities.end(), 0.0) > 0;
    if (o.sharp || !o.phantom.empty())
        std::copy_if(options.errors.begin(), options.errors.end(), std::back_inserter(options.sharp_errors), [](double e) { return e > 0; });
    const std::size_t mesh_count = options.errors.size() + options.sharp_errors.size() + options.adaptivities.size() * (o.no_budget ? 1 : 2) +
                               options.decimate_fractions.size() + 1 + options.dual;  // and Marching Cubes
    refuse_beyond_memory("--samples", "the surface samples (24 bytes each)", 24.0 * double(o.samples));
    refuse_beyond_work(o.work_limit, "--samples", 2.0 * double(o.samples) * double(mesh_count),
                       "distance queries (samples both ways on " + std::to_string(mesh_count) + " meshes)", 1e-6);
    const LoadedGrid loaded = load_input(o);
    refuse_beyond_grid_estimate(o, *loaded.grid);
    options.iso = loaded.iso;
    options.inside = loaded.inside;
    if (loaded.phantom) {
        const PhantomSpec spec = *loaded.phantom;
        options.accuracy.exact_signed_distance = [spec](double x, double y, double z) {
            return phantom_signed_distance(spec, x, y, z);
        };
        options.accuracy.exact_surface_points = phantom_surface_points(spec, o.samples);
    }
    Progress progress("comparing", o.common.quiet);
    options.progress = [&](std::size_t i, std::size_t count) { progress(double(i) / double(count)); };
    const Comparison comparison = compare_meshers(*loaded.grid, options);
    const std::vector<MeshComparison>& meshes = comparison.meshes;

    nlohmann::ordered_json report;
    report["grid"] = grid_json(o, loaded, comparison.reference_triangles);
    report["meshes"] = nlohmann::ordered_json::array();
    for (const auto& m : meshes) report["meshes"].push_back(mesh_json(m));
    const std::vector<Dominance> dominance = find_dominance(comparison);
    report["dominance"] = dominance_json(dominance);
    if (!o.json.empty()) write_text_file(o.json, detail::json_text(report, 2) + "\n");
    if (!o.plot.empty()) write_text_file(o.plot, svg_plot(make_plot(report["grid"]["input"].get<std::string>(), meshes)));
    print_table(report, meshes, std::cout);
    print_dominance(dominance, meshes, std::cout);
    return kSuccess;
}

}  // namespace

void add_compare_command(CLI::App& command, CommandResult& result) {
    auto options = std::make_shared<CompareCommandOptions>();
    CompareCommandOptions& o = *options;
    input_files(command.add_option("input", o.inputs, "A scan or .vdb grid (further files: the parts of a split raw scan)"));
    command.add_option("--iso", o.iso, "Isovalue (a .vdb: default the stored one; a phantom: 0.5)");
    const auto names = phantom_preset_names();
    auto* phantom = command.add_option("--phantom", o.phantom, "Compare on a phantom instead, against its exact surface")
        ->check(CLI::IsMember(names));
    command.add_option("--size", o.size, "--phantom: edge of the cubic volume in voxels")
        ->check(kFinitePositive)
        ->capture_default_str()
        ->needs(phantom);
    command.add_option("--blur", o.blur, "--phantom: half-width of the density ramp in voxels")
        ->check(kFiniteNonNegative)
        ->capture_default_str()
        ->needs(phantom);
    command.add_option("--error", o.errors, "Error tolerances (voxels) of the default mesher (intersection-free DC), one mesh each")
        ->capture_default_str();
    command.add_option("--dmc-error", o.dmc_errors, "Retired with dmc: refused, naming --error")->group("");
    command.add_option("--adaptivity", o.adaptivities, "volumeToMesh adaptivities in [0, 1], one mesh each")
        ->capture_default_str();
    command.add_flag("--no-budget", o.no_budget,
                     "No triangle-budget rows (by default, one per --adaptivity: the budget at that volumeToMesh mesh's triangles)");
    command.add_flag("--no-dual", o.no_dual,
                     "No dual-surface row (by default, with --adaptivity 0: mesh --method dual, the mesh of ours meant to meet volumeToMesh there)");
    command.add_flag("--sharp", o.sharp,
                     "Also DC --sharp (mesh --sharp) at each --error above 0, one mesh each; always on a --phantom");
    command.add_option("--decimate", o.decimate,
                       "Shares of triangles in (0, 1] to keep of the error-0 mesh (as mesh --decimate), one mesh each");
    const std::map<std::string, Inside> sides = {{"above", Inside::above}, {"below", Inside::below}};
    command.add_option("--inside", o.inside, "Which side of the isovalue is the object: above|below")
        ->transform(CLI::CheckedTransformer(sides, CLI::ignore_case))
        ->default_str("above");
    command.add_option("--samples", o.samples, "Points sampled on each mesh and on the true surface")
        ->check(kFinitePositive)
        ->capture_default_str();
    output_file(command.add_option("--json", o.json, "Write the whole report as JSON to FILE"));
    output_file(command.add_option("--plot", o.plot, "Write triangles against Hausdorff distance as an SVG chart to FILE"));
    add_read_flags(command, o.read);
    add_common_options(command, o.common);
    add_work_limit_option(command, o.work_limit);
    add_memory_option(command, o.memory, "the grid once converted (the conversion itself is not bounded)");
    command.callback([options, &result] { result.status = run_compare(*options); });
}

}  // namespace vdbmesh::cli
