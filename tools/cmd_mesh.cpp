// `vdbmesh mesh`: a .vdb grid or a scan (converted on the fly) to a triangle mesh file. It
// reports its figures on stderr, or with --json as one JSON object on stdout. With --verify the
// whole mesh is checked as `vdbmesh check` does (the meshers never run that check themselves);
// a defective mesh is reported, not written, and the exit status is 3. With --labels the input
// is a label map meshed per label (label_mesh_command.h).

#include <algorithm>
#include <cctype>
#include <chrono>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "common_options.h"
#include "label_mesh_command.h"
#include "load_grid.h"
#include "mesh_processing.h"
#include "option_checks.h"
#include "report_json.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/ranks.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/mesh_budget.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/mesh_range_file.h"
#include "vdbmesh/mesh_refusals.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/read.h"

namespace vdbmesh::cli {

namespace {

// "dmc" stays accepted so that scripts keep working: Dual Marching Cubes was retired, dc runs
// instead (docs/dmc.md).
const std::map<std::string, MeshMethod> kMethods = {
    {"dmc", MeshMethod::dc}, {"mc", MeshMethod::mc}, {"openvdb", MeshMethod::openvdb}, {"dc", MeshMethod::dc}, {"dual", MeshMethod::dual}};
const std::map<std::string, Inside> kSides = {{"above", Inside::above}, {"below", Inside::below}};

/// --triangles: a whole number from 1 to the most a mesh's 32-bit indices allow.
const CLI::Validator kTriangleCount(
    [](std::string& text) -> std::string {
        const bool digits = !text.empty() && text.size() <= 10 &&
                            std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
        if (!digits || std::stoull(text) < 1 || std::stoull(text) > 0xffffffffull)
            return "expected a whole number of triangles from 1 to 4294967295, got " + text;
        return {};
    },
    "N >= 1");

struct MeshCommandOptions {
    std::vector<std::string> inputs;  ///< the input, then the further parts of a split raw scan
    std::string output;
    std::optional<double> iso;
    std::string method = "dc";
    std::optional<std::string> inside;  ///< default: above, below for a level set
    MeshOptions mesh;
    bool ascii = false;
    bool normals = false;
    bool json = false;
    bool verify = false;
    std::string memory;  ///< --memory SIZE, empty when not given
    std::optional<std::uint64_t> triangles;  ///< --triangles N: the budget (mesh_budget.h)
    ReadFlags read;
    ProcessingOptions processing;
    CommonOptions common;
    LabelMeshRequest labels;  ///< used with --labels (its inputs, output, read and common options are copied in)
};

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

/// How the input is converted when it is a scan.
ConvertOptions mesh_conversion(const MeshCommandOptions& options, Progress& progress) {
    ConvertOptions convert;
    convert.band = conversion_band(options.processing);
    convert.progress = [&progress](double fraction) { progress(0.5 * fraction); };
    return convert;
}

/// The side --inside names, if given.
std::optional<Inside> given_side(const MeshCommandOptions& options) {
    return options.inside ? std::optional<Inside>(kSides.at(lowercase(*options.inside))) : std::nullopt;
}

/// The grid to mesh, with options.mesh.iso and inside set: a .vdb as stored, a scan converted
/// (band 1) closed at its box on either side (load_grid()).
openvdb::FloatGrid::Ptr load_mesh_grid(MeshCommandOptions& options, Progress& progress) {
    const GridInput loaded =
        load_grid(options.inputs, options.iso, options.read, "mesh", mesh_conversion(options, progress), "--iso", given_side(options));
    options.mesh.iso = loaded.iso;
    options.mesh.inside = loaded.inside;
    return loaded.grid;
}

/// What was made: the settings that made it, then its figures (the setting a method does not
/// use is null).
nlohmann::ordered_json figures_json(const MeshCommandOptions& options, const ProcessingReport& processing, const MeshReport& report,
                                    std::uint64_t triangles, std::uint64_t vertices, const std::optional<MeshAnalysis>& verified,
                                    double seconds) {
    const bool dc = options.mesh.method == MeshMethod::dc, openvdb = options.mesh.method == MeshMethod::openvdb;
    nlohmann::ordered_json j;
    j["output"] = options.output;
    j["method"] = lowercase(options.method);
    j["iso"] = options.iso.value_or(options.mesh.iso);  // as asked: mesh.iso is its negative for a scan's object below
    j["error"] = dc ? nlohmann::ordered_json(options.mesh.error) : nlohmann::ordered_json(nullptr);
    j["sharp"] = options.mesh.sharp;
    j["adaptivity"] = openvdb ? nlohmann::ordered_json(options.mesh.adaptivity) : nlohmann::ordered_json(nullptr);
    j["triangle_budget"] = options.triangles ? nlohmann::ordered_json(*options.triangles) : nlohmann::ordered_json(nullptr);
    j["processing"] = processing_json(options.processing, processing);
    j["triangles"] = triangles;
    j["vertices"] = vertices;
    j["seconds"] = seconds;
    // What the mesher did: its phases in the order run, fallbacks.
    j["phases"] = phases_json(report);
    j["fallbacks"] = report.fallbacks;
    // How --memory cut the grid (null when it was meshed whole).
    j["bricks"] = report.bricks == 0 ? nlohmann::ordered_json(nullptr)
                                     : nlohmann::ordered_json{{"nodes_across", {report.brick_shape.nodes_x, report.brick_shape.nodes_y}},
                                                              {"count", report.bricks},
                                                              {"estimated_peak_bytes", report.estimated_peak_bytes}};
    j["verified"] = verified ? report_json(*verified) : nlohmann::ordered_json(nullptr);
    return j;
}

/// --memory in bytes, if given (0 when not, under mpirun), when the mesh is made brick by brick;
/// refused (a usage error) with a method that meshes only whole grids, or with the processing
/// that needs the whole mesh.
std::optional<std::uint64_t> memory_limit(const MeshCommandOptions& options) {
    if (options.memory.empty() && rank_count() == 1) return std::nullopt;
    const std::string why = options.memory.empty() ? "mpirun" : "--memory";
    if (options.mesh.method == MeshMethod::openvdb) {
        throw UsageError(why + ": --method openvdb (volumeToMesh) meshes the whole grid at once" +
                         (why == "mpirun" ? std::string(", in one process (run it without mpirun)") : std::string()) +
                         "; --method dc and mc mesh by bricks");
    }
    const ProcessingOptions& p = options.processing;
    if (options.verify || options.normals || p.taubin > 0 || p.decimate || p.max_error) {
        throw UsageError(why + ": the mesh is written as a stream, never held whole, so --verify, --normals, --taubin, --decimate and "
                         "--max-error (which need the whole mesh) are not available with it");
    }
    return options.memory.empty() ? 0 : parse_memory_size("--memory", options.memory);
}

/// Sends the bricked mesh into the output file as it comes.
class FileSink final : public MeshStreamSink {
public:
    FileSink(const MeshCommandOptions& options, const openvdb::FloatGrid& grid) : options_(options), grid_(grid) {}
    void begin(std::uint64_t vertex_count, std::uint64_t triangle_count) override {
        counted(vertex_count, triangle_count);
        writer_.emplace(options_.output, MeshWriteOptions{options_.ascii, false}, vertex_count, triangle_count);
    }
    void vertex(const std::array<float, 3>& position) override { writer_->add_vertex(position); }
    void triangle(const std::array<std::uint32_t, 3>& t, const std::array<std::array<float, 3>, 3>& corners) override {
        writer_->add_triangle(t, corners);
    }
    bool needs_corners() const override { return MeshStreamWriter::writes_corners(options_.output); }
    MeshRangeSink* ranges() override { return &range_file_; }
    /// Writes the file when the mesh came as a stream: on the rank that received it (rank 0),
    /// nothing elsewhere; ranks that wrote the file together (ranges()) committed it already.
    void commit() {
        if (writer_) writer_->commit();
    }
    std::uint64_t vertices = 0, triangles = 0;

private:
    /// The whole mesh's counts, on every rank; an empty mesh refused.
    void counted(std::uint64_t vertex_count, std::uint64_t triangle_count) {
        if (triangle_count == 0) {
            throw no_surface_error(options_.inputs.front(), grid_, {options_.mesh.iso, options_.mesh.iso}, options_.output,
                                   grid_steps_text(options_.processing));
        }
        vertices = vertex_count;
        triangles = triangle_count;
    }
    /// The file when the ranks write it together (rank 0 commits it).
    class RangeFile final : public MeshRangeFile {
    public:
        explicit RangeFile(FileSink& sink) : MeshRangeFile(sink.options_.output, sink.options_.ascii), sink_(sink) {}
        std::string header(std::uint64_t vertex_count, std::uint64_t triangle_count) override {
            sink_.counted(vertex_count, triangle_count);
            return MeshRangeFile::header(vertex_count, triangle_count);
        }

    private:
        FileSink& sink_;
    };

    const MeshCommandOptions& options_;
    const openvdb::FloatGrid& grid_;
    std::optional<MeshStreamWriter> writer_;
    RangeFile range_file_{*this};
};

/// With --memory: the input read by region (never whole), brick by brick into the file (exit
/// status 0).
int run_bricked(MeshCommandOptions& options, std::uint64_t memory, Progress& progress, std::chrono::steady_clock::time_point start) {
    const std::string steps = grid_steps_text(options.processing);
    if (!steps.empty()) throw UsageError("--memory: " + steps + " work on the whole grid, which --memory never holds; leave them out");
    const GridRegionsInput opened =
        open_grid_regions(options.inputs, options.iso, options.read, "mesh", mesh_conversion(options, progress), "--iso", given_side(options));
    options.mesh.iso = opened.iso;
    options.mesh.inside = opened.inside;
    options.mesh.progress = [&](double fraction) { progress(0.5 + 0.5 * fraction); };
    const std::shared_ptr<const openvdb::FloatGrid> description = opened.source->description();
    FileSink sink(options, *description);
    BrickOptions bricks;
    bricks.memory_bytes = memory;
    bricks.rank = this_rank();
    bricks.ranks = rank_count();
    bricks.gather = stream_to_rank0;
    bricks.collectives = ranks_collectives();
    const MeshReport report = mesh_bricks_to_stream(*opened.source, options.mesh, bricks, sink);
    sink.commit();
    if (bricks.rank != 0) return 0;  // rank 0 wrote the file and reports
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (options.json) {
        std::cout << detail::json_text(figures_json(options, ProcessingReport{}, report, sink.triangles, sink.vertices, std::nullopt, seconds))
                  << "\n";
    } else if (!options.common.quiet) {
        std::cerr << "vdbmesh mesh: " << sink.triangles << " triangles, " << sink.vertices << " vertices, " << seconds << " s -> "
                  << options.output << "\n";
    }
    return 0;
}

/// The mesh of --triangles N (mesh_to_budget()). Refused as bad input: a budget above the
/// error-0 mesh's triangles (the most accurate mesh there is, which `--error 0` makes), and one
/// below where the decimation has to stop to keep the guarantees. options.mesh.error becomes the
/// error the budget picked (for the report).
MeshResult mesh_to_budget_checked(const openvdb::FloatGrid& grid, MeshCommandOptions& options) {
    BudgetReport budget;
    MeshResult result = mesh_to_budget(grid, options.mesh, std::size_t(*options.triangles), &budget);
    options.mesh.error = budget.error;
    if (result.mesh.triangles.empty()) return result;  // (no surface: reported as such)
    const std::string refusal = budget_refusal(OptionStyle::command_line, *options.triangles, result.mesh.triangles.size(), budget);
    if (!refusal.empty()) throw Error(refusal);
    return result;
}

/// Exit status 0, or 3 when --verify found a defect (the mesh is then not written).
int run_mesh(MeshCommandOptions& options) {
    if (options.labels.label.labels) {
        LabelMeshRequest& request = options.labels;
        request.inputs = options.inputs, request.output = options.output, request.ascii = options.ascii;
        request.json = options.json, request.read = options.read, request.common = options.common;
        return run_label_mesh(request);
    }
    const std::string extension = lowercase_extension(options.output);
    if (extension != ".stl" && extension != ".ply" && extension != ".obj") {
        throw UsageError("-o: expected a .stl, .ply or .obj file, got \"" + options.output + "\"");
    }
    // Both words were checked (IsMember, any case).
    options.mesh.method = kMethods.at(lowercase(options.method));
    if (lowercase(options.method) == "dmc") {
        if (!options.common.quiet) std::cerr << "vdbmesh mesh: dmc was retired: it runs dc, see docs/dmc.md\n";
        options.method = "dc";
    }
    const std::optional<std::uint64_t> memory = memory_limit(options);
    const ThreadLimit limit(options.common);
    const auto start = std::chrono::steady_clock::now();
    Progress progress("meshing", options.common.quiet || this_rank() != 0);
    if (memory) return run_bricked(options, *memory, progress, start);
    openvdb::FloatGrid::Ptr grid = load_mesh_grid(options, progress);
    ProcessingReport processing;
    process_grid(grid, options.mesh, options.processing, processing);
    options.mesh.progress = [&](double fraction) { progress(0.5 + 0.5 * fraction); };
    MeshResult result = options.triangles ? mesh_to_budget_checked(*grid, options) : mesh_grid(*grid, options.mesh);
    result.mesh = process_mesh(std::move(result.mesh), options.processing, processing);
    const Mesh& mesh = result.mesh;
    if (mesh.triangles.empty())
        throw no_surface_error(options.inputs.front(), *grid, {options.mesh.iso, options.mesh.iso}, options.output,
                               grid_steps_text(options.processing));
    std::optional<MeshAnalysis> verified;
    if (options.verify) verified = analyze_mesh(mesh);
    const bool defective = verified && !verified->is_clean();
    if (!defective) write_mesh(mesh, options.output, MeshWriteOptions{options.ascii, options.normals});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (options.json) {
        std::cout << detail::json_text(figures_json(options, processing, result.report, mesh.triangles.size(), mesh.vertices.size(), verified, seconds))
                  << "\n";
    } else if (!options.common.quiet || defective) {
        for (const std::string& fallback : result.report.fallbacks) std::cerr << "vdbmesh mesh: fell back to " << fallback << "\n";
        if (defective) {
            std::cerr << "vdbmesh mesh: --verify: the mesh is not clean (" << verified->self_intersecting_pairs
                      << " self-intersecting pairs, " << verified->boundary_edges << " boundary edges, "
                      << verified->nonmanifold_edges << " non-manifold edges, " << verified->nonmanifold_vertices
                      << " non-manifold vertices, " << verified->misoriented_edges << " misoriented edges, "
                      << verified->degenerate_faces << " degenerate faces); " << options.output << " not written\n";
        } else {
            std::cerr << "vdbmesh mesh: " << mesh.triangles.size() << " triangles, " << mesh.vertices.size()
                      << " vertices, " << seconds << " s -> " << options.output << (verified ? " (verified clean)" : "") << "\n";
        }
    }
    return defective ? 3 : 0;
}

/// --triangles picks the error and decimates itself: refused with another method, --error, the
/// decimation options and --memory (a budget needs the whole mesh).
void refuse_budget_conflicts(const MeshCommandOptions& options, const CLI::Option* triangles, const CLI::Option* error) {
    if (!options.triangles) return;
    const std::string method = lowercase(options.method);
    refuse_unless(triangles, method == "dc" || method == "dmc", "with --method dc, got --method " + method);
    refuse_unless(error, false, "without --triangles (the budget picks the error), got --triangles");
    const ProcessingOptions& p = options.processing;
    if (p.decimate || p.max_error || !options.memory.empty() || options.mesh.open_boundary)
        throw UsageError("--triangles: decimates to the budget itself and needs the whole, closed mesh; leave out --decimate, "
                         "--max-error, --memory and --open-boundary");
}

}  // namespace

void add_mesh_command(CLI::App& command, CommandResult& result) {
    auto options = std::make_shared<MeshCommandOptions>();
    input_files(command.add_option("INPUT", options->inputs, "A .vdb grid or a scan (extra files: the parts of a split raw scan)"))
        ->required();
    output_file(command.add_option("-o,--output", options->output, "Mesh file: .stl, .ply or .obj (with --labels: DIR/, .ply or .glb/.gltf)"))->required();
    auto* iso = command.add_option("--iso", options->iso, "Isovalue (default for a .vdb: the one stored by convert)");
    auto* method = command.add_option("--method", options->method,
                       "Mesher: dc (intersection-free Dual Contouring, the default), mc, openvdb (volumeToMesh), dual (experimental: docs/dmc.md, \"Error 0: the dual mesh\"); dmc was retired: it runs dc")
        ->check(CLI::IsMember(kMethods, CLI::ignore_case))
        ->capture_default_str();
    auto* error = command.add_option("--error", options->mesh.error, "dc: tolerated error in voxels (0: no simplification, Marching Cubes)")
        ->check(kFiniteNonNegative)
        ->capture_default_str();
    auto* adaptivity = command.add_option("--adaptivity", options->mesh.adaptivity, "openvdb: volumeToMesh adaptivity in [0, 1]")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    auto* inside = command.add_option("--inside", options->inside,
                       "Which side of the isovalue is the object: above|below (default: above; below for a level set)")
        ->check(CLI::IsMember(kSides, CLI::ignore_case));
    auto* open_boundary = command.add_flag("--open-boundary", options->mesh.open_boundary,
                     "Leave the surface open where it meets the edge of the scan");
    command.add_flag("--ascii", options->ascii, "ASCII STL or PLY instead of binary");
    auto* normals = command.add_flag("--normals", options->normals, "Per-vertex normals (PLY, OBJ)");
    command.add_flag("--json", options->json, "Print the figures as one JSON object on stdout");
    auto* verify = command.add_flag("--verify", options->verify,
                     "Check the whole mesh as `vdbmesh check` does; a defect: nothing written, exit status 3");
    auto* triangles = command.add_option("--triangles", options->triangles,
                          "dc: at most N triangles, the closest such mesh (DC, then the guaranteed decimator); not with --error")
        ->check(kTriangleCount);
    auto* sharp = command.add_flag("--sharp", options->mesh.sharp,
                      "dc, --error above 0: vertices on sharp edges and corners, up to a voxel beyond the error there (docs/dmc.md)");
    auto* memory = command.add_option("--memory", options->memory,
                       "Mesh brick by brick within about SIZE bytes (K, M, G suffixes; dc and mc): the same mesh");
    add_read_flags(command, options->read);
    // What shapes one surface means nothing to a label map, meshed per label: refused with --labels.
    std::vector<const CLI::Option*> one_surface = add_processing_options(command, options->processing);
    one_surface.insert(one_surface.end(), {iso, method, error, adaptivity, inside, open_boundary, normals, verify, memory, triangles, sharp});
    add_common_options(command, options->common);
    add_label_flags(command, options->labels.label, "Mesh a label map: all, or a list like 3,5,10-12; one closed mesh per label, walls shared");
    const CLI::Option* format = command.add_option("--format", options->labels.format, "--labels into a folder: the files' format")
        ->check(CLI::IsMember({"stl", "ply", "obj"}))
        ->capture_default_str();
    const CLI::Option* smooth_iterations = command.add_option("--smooth-iterations", options->labels.smooth_iterations, "--labels: constrained smoothing passes (0: voxel faces)")
        ->check(CLI::Range(0, 1000))
        ->capture_default_str();
    command.callback([options, &result, one_surface, error, adaptivity, format, smooth_iterations, triangles] {
        const std::string method = lowercase(options->method);
        const bool labels = bool(options->labels.label.labels);
        refuse_unless(format, labels, "with --labels, got none");
        refuse_unless(smooth_iterations, labels, "with --labels, got none");
        for (const CLI::Option* option : one_surface)
            refuse_unless(option, !labels, "without --labels (a label map is meshed per label), got --labels");
        refuse_unless(error, method == "dc" || method == "dmc", "with --method dc or dmc, got --method " + method);
        refuse_unless(adaptivity, method == "openvdb", "with --method openvdb, got --method " + method);
        const std::string sharp_refused = sharp_refusal(OptionStyle::command_line, options->mesh.sharp, kMethods.at(method),
                                                        options->mesh.error, options->triangles.has_value());
        if (!sharp_refused.empty()) throw UsageError(sharp_refused);
        refuse_budget_conflicts(*options, triangles, error);
        result.status = run_mesh(*options);
    });
}

}  // namespace vdbmesh::cli
