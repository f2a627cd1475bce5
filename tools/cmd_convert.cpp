// `vdbmesh convert INPUT [MORE_PARTS...] (--iso V | --iso auto | --iso-range A,B) [--band N]
// -o OUT.vdb`: streams a scan into a sparse grid (convert_to_grid, include/vdbmesh/grid.h) and
// writes it atomically. `--iso auto` takes Otsu's threshold from one extra pass over the file.

#include <iostream>
#include <memory>
#include <utility>

#include "cli.h"
#include "commands.h"
#include "common_options.h"
#include "load_grid.h"
#include "option_checks.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/scan_regions.h"
#include "vdbmesh/volume_stats.h"
#include "work_limits.h"

namespace vdbmesh::cli {
namespace {

struct ConvertCommandOptions {
    std::vector<std::string> inputs;
    std::string iso, iso_range, output;
    int band = 1;
    ReadFlags read;
    MemoryLimit memory;
    CommonOptions common;
};

/// The isovalue (or range) of the command line; `auto` reads the scan once for Otsu's threshold.
void set_isovalue(const ConvertCommandOptions& o, const ReadOptions& read, ConvertOptions& options) {
    if (!o.iso_range.empty()) {
        const auto range = parse_number_list("--iso-range", o.iso_range);
        if (range.size() != 2 || range[0] > range[1])
            throw UsageError("--iso-range: expected A,B with A <= B, got \"" + o.iso_range + "\"");
        options.iso_range = std::make_pair(range[0], range[1]);
    } else if (o.iso == "auto") {
        auto reader = open_volume(o.inputs.front(), read);
        Progress progress("statistics", o.common.quiet);
        const VolumeStats stats = compute_volume_stats(*reader, [&](double f) { progress(f); });
        options.iso = stats.suggested_iso;
        if (!o.common.quiet) std::cerr << "--iso auto: " << options.iso << " (" << stats.suggested_reason << ")\n";
    } else if (!o.iso.empty()) {
        const auto iso = parse_number_list("--iso", o.iso);
        if (iso.size() != 1) throw UsageError("--iso: expected one number or auto, got \"" + o.iso + "\"");
        options.iso = iso.front();
    } else {
        throw UsageError("convert needs --iso V, --iso-range A,B, or --iso auto (Otsu's threshold, which "
                         "`vdbmesh info` shows)");
    }
}

/// --memory: the grid is written whole (a .vdb cannot be written in parts), so the need is the
/// grid's and the converter's windows while it reads; the scan is surveyed first (one more pass
/// over the file, holding one band) to count the active voxels of each 128^3 node.
void refuse_beyond_estimate(const ConvertCommandOptions& o, const ReadOptions& read, const ConvertOptions& options) {
    Progress progress("surveying for --memory", o.common.quiet);
    ConvertOptions survey = options;
    survey.progress = [&](double f) { progress(f); };
    const std::string first = o.inputs.front();
    const auto source =
        open_scan_regions([first, read] { return std::unique_ptr<SliceReader>(open_volume(first, read)); }, survey, ScanRegionReads::none);
    refuse_beyond_memory(o.memory, "--memory", "the grid of " + first + " (a .vdb is written whole) and the converter's windows",
                         whole_grid_bytes(*source, true));
}

int run_convert(const ConvertCommandOptions& o) {
    const ThreadLimit limit(o.common);
    const ReadOptions read = o.read.to_read_options({o.inputs.begin() + 1, o.inputs.end()});
    const std::filesystem::path output = o.output;
    if (output.extension() != ".vdb") throw UsageError("-o: expected a .vdb path, got \"" + o.output + "\"");
    const std::filesystem::path folder = output.has_parent_path() ? output.parent_path() : ".";
    if (!std::filesystem::is_directory(folder))  // fail before a long conversion, not after
        throw Error(o.output + ": output folder \"" + folder.string() + "\" does not exist");

    ConvertOptions options;
    options.band = o.band;
    set_isovalue(o, read, options);
    if (o.memory.given()) refuse_beyond_estimate(o, read, options);
    auto reader = open_volume(o.inputs.front(), read);
    if (!o.common.quiet)
        for (const std::string& warning : reader->header().warnings) std::cerr << "vdbmesh: warning: " << warning << "\n";
    Progress progress("converting", o.common.quiet);
    options.progress = [&](double f) { progress(f); };
    const openvdb::FloatGrid::Ptr grid = convert_to_grid(*reader, options);
    if (grid->activeVoxelCount() == 0) throw no_surface_error(o.inputs.front(), *grid, options.iso_range.value_or(std::make_pair(options.iso, options.iso)), o.output);
    write_vdb(*grid, output);
    if (!o.common.quiet)
        std::cout << "wrote " << o.output << ": " << grid->activeVoxelCount() << " active voxels in "
                  << grid->tree().leafCount() << " leaves\n";
    return kSuccess;
}

}  // namespace

void add_convert_command(CLI::App& command, CommandResult& result) {
    auto options = std::make_shared<ConvertCommandOptions>();
    ConvertCommandOptions& o = *options;
    input_files(command.add_option("input", o.inputs, "Scan to convert; further files are the next parts of a split raw scan"))
        ->required();
    auto* iso = command.add_option("--iso", o.iso, "Isovalue V (samples above V are inside), or auto for Otsu's threshold");
    command.add_option("--iso-range", o.iso_range, "Keep the surfaces of every isovalue in A,B")->excludes(iso);
    command.add_option("--band", o.band, "Active band: straddling cells' corners dilated by N voxels (1..32)")
        ->check(CLI::Range(1, 32))
        ->capture_default_str();
    output_file(command.add_option("-o,--output", o.output, "Output .vdb file (written atomically)"))->required();
    add_read_flags(command, o.read);
    add_memory_option(command, o.memory, "a survey of the scan (one more pass over it)");
    add_common_options(command, o.common);
    command.callback([options, &result] { result.status = run_convert(*options); });
}

}  // namespace vdbmesh::cli
