// `vdbmesh view`: serves a page on 127.0.0.1 that shows a scan (re-meshed live as the
// isovalue moves), a mesh file, a label map's labels (--labels) or a splat file's splats
// alone, until Ctrl-C.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <future>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "label_view.h"
#include "common_options.h"
#include "load_grid.h"
#include "report_json.h"
#include "serve_view.h"
#include "view_splat_file.h"
#include "work_limits.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/program_memory.h"
#include "vdbmesh/splats.h"
#include "vdbmesh/view.h"

namespace vdbmesh::cli {

namespace {

struct ViewCommandOptions {
    std::vector<std::string> inputs;  ///< the input, then the further parts of a split raw scan
    std::optional<double> iso;
    std::string splat_file;  ///< --splats: where the splat tree is kept
    ViewServerOptions server;
    bool no_open = false;
    LabelFlags label;  ///< --labels: the input is a label map, shown label by label
    MemoryLimit memory;  ///< --memory: grids read by region, close-ups within it
    /// With --memory: how SIZE is shared, and the process's resident memory before the input
    /// was opened (what opening it adds is measured against it).
    std::optional<ViewMemoryPlan> memory_plan;
    std::uint64_t resident_before_opening = 0;
    ReadFlags read;
    CommonOptions common;
};

/// `view scan.splat`: a splat tree alone, without the grid it was fitted to.
ViewSource splats_alone_source(const ViewCommandOptions& options) {
    const std::string& input = options.inputs.front();
    if (options.label.labels || !options.label.names.empty()) throw UsageError("--labels: not with a splat file (" + input + ")");
    if (!options.splat_file.empty()) throw UsageError("--splats: not with a splat file as the input (" + input + ")");
    options.read.refuse_for("the splat file " + input);
    if (options.inputs.size() > 1) throw UsageError("a splat file takes no further input files");
    ViewSource source;
    source.name = std::filesystem::path(input).filename().string();
    source.splats = view_splats_alone(input, options.iso, options.common.quiet);
    source.initial_iso = source.splats->tree->iso;
    return source;
}

/// The histogram and coarse grid of a .vdb read by region, made while the page shows splats.
std::function<std::shared_ptr<const ViewScan>(const BackgroundControl&)> prepare_in_background(
    std::shared_ptr<const GridRegionSource> regions) {
    return [regions = std::move(regions)](const BackgroundControl& control) {
        return std::make_shared<const ViewScan>(prepare_grid_regions(regions, &control));
    };
}

constexpr double kMiB = 1024.0 * 1024;

std::string mib_text(std::uint64_t bytes) { return std::to_string(std::uint64_t(std::ceil(double(bytes) / kMiB))) + "M"; }

/// With --memory: the splat tree's bound once the grid is opened and its preview made (both
/// held for good), before the fit. Refused (a usage error) when it cannot hold a splat per
/// leaf of the preview (the least the fit can prune to), naming the smallest limit that can.
std::uint64_t splat_tree_bytes(const ViewCommandOptions& options, const ViewSplats& preview) {
    if (!options.memory_plan) return 0;
    const std::uint64_t resident = process_memory_now().resident;
    const std::uint64_t opened = resident > options.resident_before_opening ? resident - options.resident_before_opening : 0;
    const std::uint64_t bytes = options.memory_plan->splat_tree_bytes(opened);
    const std::uint64_t least = std::max<std::uint64_t>(preview.tree->nodes.size(), 1) * kSplatBuildBytesPerNode;
    if (bytes < least)
        throw UsageError("--memory: " + options.memory.text + " leaves " + mib_text(bytes) + " for the splat tree beside the " +
                         mib_text(opened) + " the grid holds once opened and the page's and close-ups' shares; a splat per leaf (" +
                         std::to_string(preview.tree->nodes.size()) + " nodes) needs " + mib_text(least) +
                         "; the smallest limit that could work is " + mib_text(ViewMemoryPlan::smallest_limit(opened, least)));
    if (!options.common.quiet)
        std::cerr << "vdbmesh view: --memory " << options.memory.text << ": the splat tree is fitted within " << mib_text(bytes) << " ("
                  << mib_text(opened) << " held once the grid was opened; its finest levels pruned beyond that)\n";
    return bytes;
}

/// A grid read by region with its isovalue known: the topology preview at once (seconds, no
/// value read of a .vdb); the fit, then the histogram and coarse grid, in the background.
ViewSource regions_source(std::string name, std::shared_ptr<const GridRegionSource> regions, double iso,
                          const ViewCommandOptions& options) {
    const bool quiet = options.common.quiet;
    ViewSource source;
    source.name = std::move(name);
    source.splats = topology_preview_splats(*regions, iso);
    source.initial_iso = iso;
    const std::uint64_t max_bytes = splat_tree_bytes(options, *source.splats);
    source.fit_splats = [regions, iso, max_bytes](const BackgroundControl& control) {
        return fit_view_splats(regions, iso, control, max_bytes);
    };
    source.prepare_scan = prepare_in_background(regions);
    if (!quiet)
        std::cerr << "vdbmesh view: the topology preview: " << source.splats->tree->leaf_count() << " splats in " << source.splats->seconds
                  << " s; the splat tree is fitted in the background\n";
    return source;
}

/// With --memory, a scan (not a .vdb, a mesh or a splat file): surveyed, then read by region
/// as a .vdb is (scan_regions.h), never converted whole. Its isovalue must be given: the
/// survey needs it to know where the surface is.
ViewSource scan_by_region(const ViewCommandOptions& options) {
    if (!options.iso) throw UsageError("--iso: required to view a scan with --memory (it is read by region around that surface)");
    GridRegionsInput opened = open_grid_regions(options.inputs, options.iso, options.read, "view", ConvertOptions{});
    return regions_source(std::filesystem::path(options.inputs.front()).filename().string(), std::move(opened.source), opened.iso,
                          options);
}

/// Reads the input before anything is served, so that a bad file is reported at once.
ViewSource load_source(const ViewCommandOptions& options) {
    const std::string& input = options.inputs.front();
    if (lowercase_extension(input) == ".splat") return splats_alone_source(options);
    if (options.label.labels) {
        if (options.memory.given()) throw UsageError("--memory: not with --labels (each label is meshed from the whole label map)");
        if (options.iso) throw UsageError("--iso: not with --labels (a label map is meshed label by label)");
        if (!options.splat_file.empty()) throw UsageError("--splats: not with --labels (only a .vdb scan's splat tree is kept)");
        return label_view_source(options.inputs, options.read, options.label);
    }
    if (!options.label.names.empty()) throw UsageError("--label-names: only with --labels");
    const bool vdb = lowercase_extension(input) == ".vdb";
    if (!options.splat_file.empty() && !vdb) throw UsageError("--splats: only with a .vdb input, got " + input);
    ViewSource source;
    source.name = std::filesystem::path(input).filename().string();
    if (is_mesh_file(input)) {
        if (options.memory.given())
            throw UsageError("--memory: a mesh file is shown whole, every triangle in memory; view " + input +
                             " without --memory (or check it as a stream: vdbmesh check MESH --memory SIZE)");
        if (options.iso) throw UsageError("--iso: only for a scan or .vdb input, got the mesh " + input);
        options.read.refuse_for("the mesh " + input);
        if (options.inputs.size() > 1) throw UsageError("a mesh input takes no further input files");
        source.mesh = std::make_shared<const Mesh>(read_mesh(input));
        return source;
    }
    std::optional<double> stored_iso;
    if (vdb) {
        options.read.refuse_for("the grid " + input);
        // Read by region: the server holds the coarse grid, the splat trees and the meshes
        // asked for, never the whole grid.
        // A splat file is read while the grid's topology is opened (each takes seconds on a huge scan).
        std::future<SplatTree> splat_file;
        if (!options.splat_file.empty() && std::filesystem::exists(options.splat_file))
            splat_file = std::async(std::launch::async, [file = options.splat_file] { return read_splat_file(file); });
        std::shared_ptr<const GridRegionSource> regions = open_vdb_regions(input);
        stored_iso = stored_isovalue(*regions->description());
        if (!options.splat_file.empty()) {
            // The page shows the splats at once; the histogram and coarse grid follow.
            source.splats = view_splat_file(options.splat_file, input, *regions, options.iso, stored_iso, options.common.quiet,
                                            std::move(splat_file));
            source.initial_iso = source.splats->tree->iso;
            source.prepare_scan = prepare_in_background(regions);
            return source;
        }
        if (const std::optional<double> iso = options.iso ? options.iso : stored_iso)
            return regions_source(source.name, std::move(regions), *iso, options);
        source.scan = std::make_shared<const ViewScan>(prepare_grid_regions(std::move(regions)));
    } else if (options.memory.given()) {
        return scan_by_region(options);
    } else {
        source.scan = std::make_shared<const ViewScan>(prepare_scan([&] { return open_scan(options.inputs, options.read); }));
    }
    source.initial_iso = options.iso.value_or(stored_iso.value_or(source.scan->suggested_iso));
    return source;
}

/// The figures `vdbmesh check --json` prints, for the page.
std::string check_figures(const Mesh& mesh) { return detail::json_text(report_json(analyze_mesh(mesh))); }

/// A splat file alone, or a .vdb (with its splat file, or shown first by its topology preview):
/// read in seconds (the file, the grid's topology), no pass over the voxels. The page is served
/// meanwhile, so that the browser starts while they are read (about 1.2 to 2.4 s of a first
/// picture on a busy machine, issue 30); a bad file is still an error of the command, the page
/// showing it too. (A .vdb stating no isovalue, without --iso, is prepared before the page's
/// API answers: Otsu's suggestion needs its values.) A .vdb's splat file fitted now is not.
/// A scan with --memory is served while its survey runs (a pass over the whole file).
bool read_while_serving(const ViewCommandOptions& options) {
    if (options.label.labels) return false;
    const std::string extension = lowercase_extension(options.inputs.front());
    if (extension == ".splat") return true;
    if (options.memory.given() && extension != ".vdb") return !is_mesh_file(options.inputs.front());  // a scan's survey
    if (extension != ".vdb") return false;
    return options.splat_file.empty() || std::filesystem::exists(options.splat_file);
}

/// With --memory, before anything is read: SIZE shared as ViewMemoryPlan says (a close-up's
/// read and a tree at another isovalue each within a quarter of what the program leaves).
void plan_memory(ViewCommandOptions& options) {
    if (!options.memory.given()) return;
    refuse_beyond_memory(options.memory, "--memory",
                         "a close-up's read by region (at least " + mib_text(ViewMemoryPlan::kMinCloseUpBytes) +
                             "), the page, the grid as opened and the splat tree (as much each)",
                         double(ViewMemoryPlan::smallest_limit() - kProgramBytes));
    options.memory_plan = ViewMemoryPlan{std::uint64_t(options.memory.bytes())};
    options.server.region_read_bytes = options.memory_plan->close_up_bytes();
    options.server.other_splat_tree_bytes = options.memory_plan->close_up_bytes();
    options.resident_before_opening = process_memory_now().resident;
}

void run_view(ViewCommandOptions& options) {
    plan_memory(options);
    const ThreadLimit limit(options.common);
    if (!options.common.quiet) std::cerr << "vdbmesh view: reading " << options.inputs.front() << "\n";
    options.server.mesh_figures = check_figures;
    if (read_while_serving(options)) {
        serve_view_while_loading([&options] { return load_source(options); }, options.server, options.inputs.front(),
                                 options.no_open, options.common.quiet);
        return;
    }
    ViewSource source = load_source(options);
    if (!source.labels.empty())
        options.server.mesh_figures = [labels = source.labels](const Mesh& mesh) { return label_figures(mesh, labels); };
    serve_view(std::move(source), options.server, options.inputs.front(), options.no_open, options.common.quiet);
}

}  // namespace

void add_view_command(CLI::App& command, CommandResult& result) {
    auto options = std::make_shared<ViewCommandOptions>();
    command.add_option("INPUT", options->inputs,
                       "A scan, a .vdb grid, a mesh (.stl, .ply, .obj) or a splat file (.splat, shown alone); extra files: the "
                       "parts of a split raw scan")
        ->required();
    command.add_option("--iso", options->iso, "Isovalue shown first (default: the stored one, else Otsu's)");
    command.add_option("--splats", options->splat_file,
                       "A .vdb's splat tree kept in FILE: read when it was fitted to this grid, else fitted (at --iso, "
                       "else the stored isovalue) and written; the page shows it at once")
        ->type_name("FILE");
    command.add_option("--port", options->server.port, "Port (0: any free one)")
        ->check(CLI::Range(0, 65535))
        ->capture_default_str();
    command.add_option("--host", options->server.host, "Address to listen on (others than 127.0.0.1 expose the files)")
        ->capture_default_str();
    command.add_option("--budget", options->server.triangle_budget,
                       "Full meshes with more triangles are shown coarse until asked for")
        ->capture_default_str();
    command.add_flag("--no-open", options->no_open, "Do not open a browser");
    add_memory_option(command, options->memory,
                      "the program, the grid as opened, the splat tree, the page and one close-up's read (a scan is then read "
                      "by region: surveyed once, never converted whole, --iso needed; a close-up reads at most a quarter of "
                      "SIZE; the splat tree's finer levels pruned to fit; not with a mesh file or --labels)");
    add_label_flags(command, options->label, "Show a label map: all, or a list like 3,5,10-12; each label meshed (as mesh --labels), coloured and switchable");
    add_read_flags(command, options->read);
    add_common_options(command, options->common);
    command.callback([options, &result] {
        run_view(*options);
        result.status = 0;
    });
}

}  // namespace vdbmesh::cli
