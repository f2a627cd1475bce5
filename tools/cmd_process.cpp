// `vdbmesh process IN.vdb [--deposit D] [--etch AXIS:DEPTH] ... [--stop-layer STOP.vdb] -o OUT.vdb`:
// process steps on a level set (negative inside), in the order given, each on the shared tree
// (include/vdbmesh/shared_process.h, issue 14): --deposit grows the solid by D (world units),
// --etch z:2 removes material up to 2 below the surfaces exposed towards +z (-z:2 towards -z),
// never removing or etching through the --stop-layer solid.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "commands.h"
#include "common_options.h"
#include "load_grid.h"
#include "option_checks.h"
#include "work_limits.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/shared_process.h"
#include "vdbmesh/shared_tree.h"

namespace vdbmesh::cli {
namespace {

struct ProcessCommandOptions {
    std::string input, output, stop_layer;
    std::vector<double> deposits;
    std::vector<std::string> etches;
    bool json = false;
    CommonOptions common;
    WorkLimit work_limit;
    MemoryLimit memory;
};

struct Etch {
    int axis = 2, sign = 1;
    double depth = 0;
};

Etch parse_etch(const std::string& text) {
    const auto colon = text.find(':');
    std::string axis = colon == std::string::npos ? "" : text.substr(0, colon);
    Etch e;
    if (!axis.empty() && (axis[0] == '-' || axis[0] == '+')) {
        e.sign = axis[0] == '-' ? -1 : 1;
        axis = axis.substr(1);
    }
    if (axis != "x" && axis != "y" && axis != "z") {
        throw UsageError("--etch: expected AXIS:DEPTH with AXIS x, y or z (optionally -x ...), got \"" + text + "\"");
    }
    e.axis = axis[0] - 'x';
    try {
        std::size_t used = 0;
        e.depth = std::stod(text.substr(colon + 1), &used);
        if (used != text.size() - colon - 1) throw std::invalid_argument("trailing");
    } catch (const std::exception&) {
        throw UsageError("--etch: expected a depth after \"" + text.substr(0, colon + 1) + "\", got \"" + text.substr(colon + 1) + "\"");
    }
    if (!(e.depth >= 0) || !std::isfinite(e.depth)) throw UsageError("--etch: expected a non-negative depth, got \"" + text + "\"");
    return e;
}

/// The grid of @a path; a grid of another class (a density .vdb from `convert`) is bad input.
openvdb::FloatGrid::Ptr read_level_set(const std::string& path) {
    openvdb::FloatGrid::Ptr grid = read_vdb(path);
    if (grid->getGridClass() != openvdb::GRID_LEVEL_SET)
        throw FormatError(path, "grid class", "a level set (negative inside; `vdbmesh lattice` or `reconstruct` write one)",
                          "\"" + openvdb::GridBase::gridClassToString(grid->getGridClass()) + "\" (a density grid from `convert`?)");
    return grid;
}

/// Refuses steps whose leaf visits (each pass maps every leaf, about 1 ms each: a deposit of 10
/// on a 2-wide lattice, 5400 visits in 4.7 s) or leaves exceed the limits. A deposit of D grows
/// the box by 2 D and the surface's leaves with its square, in passes of at most 7 voxels
/// (shared_deposit); an etch passes at most 8 voxels at a time (shared_etch). Memory: @a held
/// (the grids read), the grown leaves twice (a step's input and output trees), and with --memory
/// the result's float grid too, built while the last tree lives.
void refuse_unbounded_steps(const WorkLimit& limit, const MemoryLimit& memory, double held, const openvdb::FloatGrid& input,
                            const std::vector<std::string>& order, const std::vector<double>& deposits, const std::vector<Etch>& etches) {
    const double voxel = input.voxelSize()[0];
    const openvdb::CoordBBox box = input.evalActiveVoxelBoundingBox();
    double extent = voxel * double(std::max(1, (box.dim()[0] + box.dim()[1] + box.dim()[2]) / 3));
    double leaves = double(std::max<openvdb::Index64>(1, input.tree().leafCount())), visits = 0;
    std::size_t next_deposit = 0, next_etch = 0;
    for (const std::string& step : order) {
        const bool deposit = step == "deposit";
        const double distance = deposit ? deposits[next_deposit++] : etches[next_etch++].depth;
        const double passes = std::max(1.0, std::ceil(distance / voxel / (deposit ? 7.0 : 8.0)));
        const double grown = deposit ? extent + 2 * distance : extent;
        leaves *= (grown / extent) * (grown / extent);
        extent = grown;
        visits += passes * leaves;
        const std::string option = deposit ? "--deposit" : "--etch";
        refuse_beyond_work(limit, option, visits, "leaf visits in passes over the grown surface", 1e-3);
        refuse_beyond_memory(option, "the grown level set's leaves, twice", 2.0 * sizeof(SharedLeaf) * leaves);
        const double result = kFloatLeafBytes * leaves;
        refuse_beyond_memory(memory, option, "the grids read, the grown level set's leaves twice and the result",
                             held + 2.0 * sizeof(SharedLeaf) * leaves + result);
    }
}

int run_process(const ProcessCommandOptions& o, const std::vector<std::string>& order) {
    if (lowercase_extension(o.input) != ".vdb") throw UsageError("INPUT: expected a .vdb level set, got \"" + o.input + "\"");
    if (lowercase_extension(o.output) != ".vdb") throw UsageError("-o: expected a .vdb file, got \"" + o.output + "\"");
    if (order.empty()) throw UsageError("process: expected at least one step (--deposit or --etch), got none");
    for (double d : o.deposits) {
        if (!(d >= 0) || !std::isfinite(d)) throw UsageError("--deposit: expected a non-negative distance, got " + std::to_string(d));
    }
    std::vector<Etch> etches;
    for (const std::string& e : o.etches) etches.push_back(parse_etch(e));
    if (!o.stop_layer.empty() && o.etches.empty()) throw UsageError("--stop-layer: only with --etch");
    const ThreadLimit limit(o.common);
    const auto start = std::chrono::steady_clock::now();
    const openvdb::FloatGrid::Ptr input = read_level_set(o.input);
    openvdb::FloatGrid::Ptr stop;
    if (!o.stop_layer.empty()) {
        stop = read_level_set(o.stop_layer);
        if (std::abs(stop->voxelSize()[0] - input->voxelSize()[0]) > 1e-9 * input->voxelSize()[0]) {
            throw UsageError("--stop-layer: expected the voxel size of " + o.input + " (" + std::to_string(input->voxelSize()[0]) + "), got " +
                             std::to_string(stop->voxelSize()[0]));
        }
    }
    // --memory: the grids are read whole first (every step needs every leaf), then the steps are
    // estimated with them, before any step runs.
    const double held = double(input->memUsage()) + (stop ? double(stop->memUsage()) : 0);
    refuse_unbounded_steps(o.work_limit, o.memory, held, *input, order, o.deposits, etches);
    SharedTree tree = build_shared_tree(*input);
    nlohmann::ordered_json steps = nlohmann::ordered_json::array();
    std::size_t next_deposit = 0, next_etch = 0;
    for (const std::string& step : order) {
        const auto t = std::chrono::steady_clock::now();
        nlohmann::ordered_json j;
        if (step == "deposit") {
            const double d = o.deposits[next_deposit++];
            tree = shared_deposit(tree, d);
            j["deposit"] = d;
        } else {
            const Etch& e = etches[next_etch++];
            tree = shared_etch(tree, e.axis, e.sign, e.depth, stop.get());
            j["etch"] = o.etches[next_etch - 1];
        }
        j["unique_leaves"] = tree.leaves.size();
        j["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
        steps.push_back(j);
    }
    const auto grid = to_float_grid(tree);
    grid->setName(input->getName());
    write_vdb(*grid, o.output);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.json) {
        std::cout << detail::json_text(nlohmann::ordered_json{{"steps", steps}, {"leaves", grid->tree().leafCount()}, {"seconds", seconds}}) << "\n";
    } else if (!o.common.quiet) {
        std::cerr << "vdbmesh process: " << order.size() << " steps, " << seconds << " s -> " << o.output << "\n";
    }
    return 0;
}

}  // namespace

void add_process_command(CLI::App& command, CommandResult& result) {
    auto o = std::make_shared<ProcessCommandOptions>();
    replaceable_input(command.add_option("INPUT", o->input, "A .vdb level set (negative inside)"))->required();
    output_file(command.add_option("-o,--output", o->output, "The result: a .vdb level set (may be INPUT: replaced once the run succeeded)"))
        ->required();
    auto* deposit = command.add_option("--deposit", o->deposits, "Grow the solid by this distance (world units); repeatable, in order");
    auto* etch = command.add_option("--etch", o->etches, "AXIS:DEPTH, e.g. z:2 (exposed towards +z) or -z:2; repeatable, in order");
    deposit->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)->allow_extra_args(false);
    etch->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)->allow_extra_args(false);
    input_files(command.add_option("--stop-layer", o->stop_layer, "A .vdb level set that etching never removes nor passes"));
    command.add_flag("--json", o->json, "Print the figures as one JSON object on stdout");
    add_common_options(command, o->common);
    add_work_limit_option(command, o->work_limit);
    add_memory_option(command, o->memory, "the level sets read and the steps");
    command.callback([o, &result, &command, deposit, etch] {
        std::vector<std::string> order;
        for (const CLI::Option* opt : command.parse_order()) {
            if (opt == deposit) order.push_back("deposit");
            else if (opt == etch) order.push_back("etch");
        }
        result.status = run_process(*o, order);
    });
}

}  // namespace vdbmesh::cli
