// `vdbmesh lattice KIND --period P (--thickness T | --level L) --box X,Y,Z --voxel V
//  [--clip SOLID] (-o OUT | --measure) [--json]`: a periodic lattice (gyroid, Schwarz P, diamond,
// body-centred struts) built as a shared tree (include/vdbmesh/shared_tree.h, issue 14), so that
// each distinct leaf is evaluated and stored once. Sizes are in world units.
//  - -o x.vdb: the expanded level set; -o x.stl/.ply/.obj: its Marching Cubes surface, memoised
//    per leaf neighbourhood; -o x.gltf/.glb: the same surface instanced (distinct block meshes
//    and their translations, EXT_mesh_gpu_instancing), for surfaces too large to write flat.
//  - --measure: volume, area, components, voxels, unique and represented leaves, nothing written.
//  - --view: the page of `vdbmesh view` showing the lattice by its splat hierarchy, fitted with
//    result matching on the shared tree (include/vdbmesh/shared_splats.h), until Ctrl-C.
// --clip intersects the lattice with a solid: a mesh file, or a .vdb / scan meshed as `measure` does.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <numeric>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli.h"
#include "commands.h"
#include "common_options.h"
#include "gltf_instanced.h"
#include "load_grid.h"
#include "load_mesh.h"
#include "option_checks.h"
#include "serve_view.h"
#include "work_limits.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/lattice.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/shared_splats.h"
#include "vdbmesh/shared_tree.h"
#include "vdbmesh/view.h"

namespace vdbmesh::cli {
namespace {

struct LatticeCommandOptions {
    std::string kind;
    double period = 0;
    std::optional<double> thickness, level;
    std::string box, box_min;
    double voxel = 0;
    double band = 3;
    std::vector<std::string> clip;
    MeshInputOptions clip_input;
    std::string clip_inside = "above";
    std::string output;
    bool measure = false;
    bool view = false;
    bool no_open = false;
    ViewServerOptions server;
    bool json = false;
    bool ascii = false;
    CommonOptions common;
    WorkLimit work_limit;
    MemoryLimit memory;
};

std::array<double, 3> parse_triple(const std::string& flag, const std::string& text) {
    const std::vector<double> v = parse_number_list(flag, text);
    if (v.size() == 1) return {v[0], v[0], v[0]};
    if (v.size() != 3) throw UsageError(flag + ": expected one number or three (x,y,z), got \"" + text + "\"");
    return {v[0], v[1], v[2]};
}

/// Along one axis of the box widened by the band: the cubes of @a dim voxels that
/// build_shared_tree() builds apart. Those deep inside the box (the band from both faces) repeat
/// when the period is a whole number of voxels (@a period_voxels > 0) and are built once per
/// distinct offset, lcm(period, dim) / dim of them; the others each once.
double distinct_along(double side_voxels, double band, double dim, double period_voxels) {
    const double all = std::ceil((side_voxels + 2 * band + 2) / dim) + 1;
    if (period_voxels <= 0) return all;
    const double deep = std::max(0.0, std::floor((side_voxels - 2 * band) / dim) - 1);
    const auto period = static_cast<long long>(period_voxels), size = static_cast<long long>(dim);
    return all - deep + std::min(deep, double(std::lcm(period, size) / size));
}

/// Refuses a lattice whose leaves take more work than the run may plan for. build_shared_tree()
/// classifies the leaf positions (about 0.3 us each, counted 0.5: 15.8e6 of a periodic 2000^3
/// gyroid in 4.95 s) of the level-1 nodes (16^3 leaves) it builds apart, and evaluates the
/// distinct leaves within the band of the surface (about 8.3 us each, counted 9: 456533 at
/// --band 300 over a box of 8 voxels, in 3.79 s). The band holds the leaves the surface
/// crosses (6.2 / period of surface per unit volume: a gyroid sheet's two sides) times its
/// width, and at least the box grown by the band less a cell's diagonal (every point of the
/// box lies within that of the surface): a band wider than the box fills the widened box.
/// With --memory: the distinct leaves stored (sizeof(SharedLeaf) each), a pointer for each
/// leaf of the band, and what the output expands: a .vdb every band leaf as a float leaf, a flat
/// mesh the surface's leaves' triangles (Marching Cubes: about 2 a surface voxel on the 8 x 8
/// faces of a leaf, 128 each, at about 40 bytes with their vertices); a measure or an instanced
/// glTF little more than the tree. The --clip solid is not counted.
void refuse_unbounded_lattice(const WorkLimit& limit, const LatticeOptions& lattice, const MemoryLimit& memory = {},
                              const std::string& extension = "") {
    const double band = std::ceil(lattice.band), leaf = 8 * lattice.voxel, ratio = lattice.period / lattice.voxel;
    const double period_voxels = std::abs(ratio - std::round(ratio)) < 1e-9 * std::max(1.0, ratio) && ratio < 1e9 ? std::round(ratio) : 0;
    const double grown = band * lattice.voxel - std::sqrt(3.0) * lattice.period;  // <= 0: no leaf is sure to be in the band
    double positions = 1, volume = 1, grown_leaves = grown > 0 ? 1 : 0, distinct_leaves = 1, distinct_nodes = 1, widest = 0;
    for (const double side : lattice.box) {
        const double side_voxels = side / lattice.voxel;
        positions *= std::ceil((side_voxels + 2 * band + 2) / 8);
        volume *= side;
        grown_leaves *= std::ceil((side + 2 * std::max(0.0, grown)) / leaf);
        distinct_leaves *= distinct_along(side_voxels, band, 8, period_voxels);
        distinct_nodes *= distinct_along(side_voxels, band, 128, period_voxels);
        widest = std::max(widest, side_voxels);
    }
    const double surface_leaves = 6.2 / lattice.period * volume / (leaf * leaf);
    const double band_leaves = std::min(positions, std::max(surface_leaves * (2 * band / 8 + 2), grown_leaves));
    const double classified = std::min(positions, 4096 * distinct_nodes);
    const double evaluated = std::min(distinct_leaves, band_leaves);
    std::ostringstream units;
    units.precision(3);
    units << "leaf positions in --box and the band around it, " << evaluated << " of them evaluated,";
    const std::string option = 2 * band > widest ? "--band" : "--voxel";
    refuse_beyond_work(limit, option, classified, units.str(), (0.5e-6 * classified + 9e-6 * evaluated) / classified);
    if (!memory.given()) return;
    double output = 0;
    if (extension == ".vdb") output = band_leaves * kFloatLeafBytes;
    if (extension == ".stl" || extension == ".ply" || extension == ".obj") output = std::min(surface_leaves, band_leaves) * 128 * 40;
    refuse_beyond_memory(memory, option, "the lattice's distinct leaves, its band's leaves and the output expanded",
                         evaluated * double(sizeof(SharedLeaf)) + 8 * band_leaves + output);
}

/// The page's source: @a tree's splat hierarchy, fitted with result matching.
ViewSource lattice_source(const SharedTree& tree, const LatticeOptions& lattice, const LatticeCommandOptions& o,
                          std::chrono::steady_clock::time_point start) {
    const auto fit_start = std::chrono::steady_clock::now();
    SplatOptions options;
    options.inside = Inside::below;
    auto shown = std::make_shared<ViewLattice>();
    shown->splats = std::make_shared<const SharedSplatTree>(build_splat_tree(tree, options));
    shown->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - fit_start).count();
    for (int a = 0; a < 3; ++a) {
        shown->box_min[a] = lattice.box_min[a];
        shown->box_max[a] = lattice.box_min[a] + lattice.box[a];
    }
    if (!o.common.quiet) {
        std::cerr << "vdbmesh lattice: splats of " << shown->splats->placed.size() << " nodes of 128^3 fitted as "
                  << shown->splats->subtrees.size() << " in " << shown->seconds << " s (" << 
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s in all)\n";
    }
    ViewSource source;
    source.name = o.kind + " lattice";
    source.lattice = std::move(shown);
    return source;
}

/// Serves the page showing @a tree by its splat hierarchy until Ctrl-C. The page is served at
/// once and its API waits for the splats (seconds on a 4096^3 lattice): the browser starts
/// meanwhile (issue 30's first picture within 5 s).
void view_lattice(const SharedTree& tree, const LatticeOptions& lattice, const LatticeCommandOptions& o,
                  std::chrono::steady_clock::time_point start) {
    serve_view_while_loading([&] { return lattice_source(tree, lattice, o, start); }, o.server, o.kind + " lattice", o.no_open,
                             o.common.quiet);
}

int run_lattice(const LatticeCommandOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    LatticeOptions lattice;
    lattice.kind = parse_lattice_kind(o.kind);
    lattice.period = o.period;
    lattice.thickness = o.thickness;
    lattice.level = o.level;
    lattice.voxel = o.voxel;
    lattice.band = o.band;
    const std::string extension = lowercase_extension(o.output);
    if (int(!o.output.empty()) + int(o.measure) + int(o.view) != 1)
        throw UsageError("lattice: expected one of -o FILE, --measure and --view, got " +
                         std::to_string(int(!o.output.empty()) + int(o.measure) + int(o.view)));
    if (!o.view && o.no_open) throw UsageError("--no-open: only with --view");
    if (!o.output.empty() && extension != ".vdb" && extension != ".stl" && extension != ".ply" && extension != ".obj" &&
        extension != ".gltf" && extension != ".glb") {
        throw UsageError("-o: expected a .vdb, .stl, .ply, .obj, .gltf or .glb file, got \"" + o.output + "\"");
    }
    if (o.box.empty() && o.clip.empty()) throw UsageError("--box: expected the lattice's size (x,y,z in world units) or a --clip solid, got neither");
    if (!o.box.empty()) lattice.box = parse_triple("--box", o.box);
    if (!o.box_min.empty()) lattice.box_min = parse_triple("--box-min", o.box_min);
    if (o.clip.empty() || !o.box.empty()) check_lattice_options(lattice);  // with --clip alone: once its box is known
    if (!o.box.empty()) refuse_unbounded_lattice(o.work_limit, lattice, o.memory, extension);
    const ThreadLimit limit(o.common);
    Progress progress("lattice", o.common.quiet);

    std::shared_ptr<openvdb::FloatGrid> clip;
    if (o.clip.empty()) o.clip_input.read.refuse_for("no --clip");
    if (!o.clip.empty()) {
        MeshInputOptions clip_input = o.clip_input;
        clip_input.inside = o.clip_inside == "below" ? Inside::below : Inside::above;
        clip_input.iso_option = "--clip-iso";
        const Mesh solid = load_mesh(o.clip, clip_input, "clip with");
        if (o.box.empty()) {
            // The solid's bounding box.
            std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
            for (const auto& v : solid.vertices)
                for (int a = 0; a < 3; ++a) {
                    lo[a] = std::min(lo[a], double(v[a]));
                    hi[a] = std::max(hi[a], double(v[a]));
                }
            for (int a = 0; a < 3; ++a) {
                lattice.box_min[a] = lo[a] - o.voxel;
                lattice.box[a] = hi[a] - lo[a] + 2 * o.voxel;
            }
            check_lattice_options(lattice);
            refuse_unbounded_lattice(o.work_limit, lattice, o.memory, extension);
        }
        clip = clip_level_set(solid, o.voxel, o.band);
    }
    progress(0.1);
    const auto field = make_lattice_field(lattice, clip.get());
    const SharedTree tree = build_shared_tree(*field);
    progress(0.5);
    const SharedStats stats = shared_stats(tree);
    nlohmann::ordered_json j;
    j["kind"] = o.kind;
    j["voxels_per_axis"] = {std::llround(lattice.box[0] / o.voxel), std::llround(lattice.box[1] / o.voxel), std::llround(lattice.box[2] / o.voxel)};
    if (o.view) {
        view_lattice(tree, lattice, o, start);
        return 0;
    }
    if (o.measure) {
        j["volume"] = shared_volume(tree);
        j["area"] = shared_area(tree);
        j["components"] = shared_components(tree);
        j["voxels"] = stats.active_voxels;
        j["unique_leaves"] = stats.stored[0];
        j["leaves"] = stats.represented[0];
    } else if (extension == ".vdb") {
        const auto grid = to_float_grid(tree);
        grid->setName("lattice");
        write_vdb(*grid, o.output);
        j["voxels"] = stats.active_voxels;
        j["unique_leaves"] = stats.stored[0];
        j["leaves"] = stats.represented[0];
    } else if (extension == ".gltf" || extension == ".glb") {
        const InstancedMesh mesh = shared_marching_cubes_instanced(tree);
        if (mesh.instances.empty()) throw Error("lattice: the lattice has no surface in the box; " + o.output + " not written");
        write_instanced_gltf(mesh, o.output);
        j["parts"] = mesh.parts.size();
        j["instances"] = mesh.instances.size();
    } else {
        const Mesh mesh = shared_marching_cubes(tree);
        if (mesh.triangles.empty()) throw Error("lattice: the lattice has no surface in the box; " + o.output + " not written");
        write_mesh(mesh, o.output, MeshWriteOptions{o.ascii, false});
        j["triangles"] = mesh.triangles.size();
        j["vertices"] = mesh.vertices.size();
    }
    progress(1.0);
    j["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.json) {
        std::cout << detail::json_text(j) << "\n";
    } else if (o.measure) {
        std::cout << "volume " << j["volume"] << "\narea " << j["area"] << "\ncomponents " << j["components"] << "\nvoxels "
                  << j["voxels"] << "\nunique_leaves " << j["unique_leaves"] << "\nleaves " << j["leaves"] << "\n";
    } else if (!o.common.quiet) {
        std::cerr << "vdbmesh lattice: " << stats.stored[0] << " distinct leaves of " << stats.represented[0] << ", "
                  << j["seconds"].get<double>() << " s -> " << o.output << "\n";
    }
    return 0;
}

}  // namespace

void add_lattice_command(CLI::App& command, CommandResult& result) {
    auto o = std::make_shared<LatticeCommandOptions>();
    command.add_option("KIND", o->kind, "gyroid, schwarz-p, diamond or bcc (body-centred struts)")->required();
    command.add_option("--period", o->period, "Cell size (world units)")->required();
    command.add_option("--thickness", o->thickness, "Sheet thickness (TPMS) or strut diameter (bcc), world units");
    command.add_option("--level", o->level, "Solid TPMS: the region where the function is below this level");
    command.add_option("--box", o->box, "Size x,y,z (or one number) in world units; default with --clip: the solid's box");
    command.add_option("--box-min", o->box_min, "Minimum corner x,y,z of the box (default 0,0,0)");
    command.add_option("--voxel", o->voxel, "Voxel size (world units)")->required();
    command.add_option("--band", o->band, "Narrow band half-width in voxels")->capture_default_str();
    auto* clip = input_files(command.add_option("--clip", o->clip,
                       "Intersect with this solid: a mesh file, or a .vdb or scan (meshed at --clip-iso; further files: "
                       "the parts of a split raw scan, read with the --raw-* flags)"));
    o->clip_input.grid_only = {
        command.add_option("--clip-iso", o->clip_input.iso, "Isovalue of a --clip .vdb or scan (default: the stored one)")->needs(clip),
        command.add_option("--clip-inside", o->clip_inside, "Which side of --clip-iso is the solid: above (default) or below (a level set)")
            ->check(CLI::IsMember({"above", "below"}))
            ->needs(clip),
    };
    output_file(command.add_option("-o,--output", o->output, "Output: .vdb (level set), .stl/.ply/.obj (mesh), .gltf/.glb (instanced mesh)"));
    command.add_flag("--measure", o->measure, "Print volume, area, components, voxels, unique_leaves, leaves; write nothing");
    command.add_flag("--view", o->view, "Show it in the browser by its splat hierarchy (as `vdbmesh view`), until Ctrl-C");
    command.add_option("--port", o->server.port, "With --view: the port (0: any free one)")->check(CLI::Range(0, 65535))->capture_default_str();
    command.add_flag("--no-open", o->no_open, "With --view: do not open a browser");
    command.add_flag("--json", o->json, "Print the figures as one JSON object on stdout");
    command.add_flag("--ascii", o->ascii, "ASCII STL or PLY");
    add_read_flags(command, o->clip_input.read);
    add_common_options(command, o->common);
    add_work_limit_option(command, o->work_limit);
    add_memory_option(command, o->memory, "the lattice's leaves and the output (not counting a --clip solid)");
    command.callback([o, &result] { result.status = run_lattice(*o); });
}

}  // namespace vdbmesh::cli
