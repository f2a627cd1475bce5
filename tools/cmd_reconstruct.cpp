// `vdbmesh reconstruct POINTS -o OUT`: points (.xyz/.pts, .ply, a .conf range-scan set) to a
// closed surface (.stl/.ply/.obj) or to the sampled field (.vdb), by the partition-of-unity
// RBF of include/vdbmesh/points.h meshed with DC.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "commands.h"
#include "common_options.h"
#include "option_checks.h"
#include "work_limits.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/parse_util.h"
#include "vdbmesh/points.h"

namespace vdbmesh::cli {

namespace {

struct ReconstructCommandOptions {
    std::string input, output;
    ReconstructOptions rec;
    bool json = false;
    bool ascii = false;
    CommonOptions common;
    WorkLimit work_limit;
    MemoryLimit memory;
};

/// Refuses a --voxel whose surface would take more memory or work than a run may plan for. The
/// surface's voxels are bounded by the area of the points' box over voxel^2; each took about
/// 2 us and 700 bytes (a sphere of radius 10 at --voxel 0.025: 6.4 s, 1.36 GB, for 3.8e6).
/// With --memory the default voxel is estimated too, with the points held (positions and
/// normals, in doubles, twice: the cloud read and the one reconstructed from).
void refuse_unbounded_sampling(const WorkLimit& limit, const MemoryLimit& memory, const PointCloud& points, double voxel) {
    if (!(voxel > 0) && !memory.given()) return;  // the default: the longest side / 256
    Vec3d lo = points.points.front(), hi = lo;
    for (const Vec3d& p : points.points)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    const Vec3d side{hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    const double planned_voxel = voxel > 0 ? voxel : std::max({side[0], side[1], side[2]}) / 256;
    const double surface_voxels = 2 * (side[0] * side[1] + side[1] * side[2] + side[2] * side[0]) / (planned_voxel * planned_voxel);
    const double point_bytes = 2 * 48.0 * double(points.points.size());
    refuse_beyond_memory(memory, "--voxel", "the points and the surface's voxels (700 bytes each)",
                         (memory.given() ? point_bytes : 0) + 700 * surface_voxels);
    if (!(voxel > 0)) return;
    refuse_beyond_work(limit, "--voxel", surface_voxels, "surface voxels", 2e-6);
}

int run_reconstruct(ReconstructCommandOptions& o) {
    const std::string ext = detail::to_lower(std::filesystem::path(o.output).extension().string());
    if (ext != ".stl" && ext != ".ply" && ext != ".obj" && ext != ".vdb")
        throw UsageError("-o: expected a .stl, .ply, .obj or .vdb file, got \"" + o.output + "\"");
    if (!(o.rec.cluster >= 0 || o.rec.cluster == -1))
        throw UsageError("--cluster: expected a cell size >= 0 or -1 (no averaging), got " + std::to_string(o.rec.cluster));
    const ThreadLimit limit(o.common);
    const auto start = std::chrono::steady_clock::now();
    Progress progress("reconstructing", o.common.quiet);
    o.rec.progress = [&](double f) { progress(f); };
    PointCloud points = read_points(o.input);
    refuse_unbounded_sampling(o.work_limit, o.memory, points, o.rec.sample.voxel);
    Reconstruction rec;
    try {
        rec = reconstruct(std::move(points), o.rec);
    } catch (const FormatError&) {
        throw;
    } catch (const Error& e) {  // "reconstruct: need at least 10 points": say which file's
        throw Error(o.input + ": " + e.what());
    }
    if (rec.mesh.triangles.empty()) throw Error(o.input + ": the reconstructed field has no surface; " + o.output + " not written");
    if (ext == ".vdb") {
        write_vdb(*rec.grid, o.output);
    } else {
        write_mesh(rec.mesh, o.output, MeshWriteOptions{o.ascii, false});
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const ReconstructReport& r = rec.report;
    if (o.json) {
        nlohmann::ordered_json j;
        j["input"] = o.input;
        j["output"] = o.output;
        j["input_points"] = r.input_points;
        j["outliers"] = r.outliers;
        j["used_points"] = r.used_points;
        j["fitted_points"] = r.fitted_points;
        j["leaves"] = r.leaves;
        j["voxel"] = r.voxel;
        j["triangles"] = rec.mesh.triangles.size();
        j["vertices"] = rec.mesh.vertices.size();
        j["dropped_components"] = r.dropped_components;
        nlohmann::ordered_json phases = nlohmann::ordered_json::object();
        for (const auto& [name, s] : r.phases) phases[name] = s;
        j["phases"] = phases;
        j["seconds"] = seconds;
        std::cout << detail::json_text(j) << "\n";
    } else if (!o.common.quiet) {
        std::cerr << "vdbmesh reconstruct: " << r.input_points << " points (" << r.outliers << " outliers, "
                  << r.used_points << " used, " << r.leaves << " leaves), voxel " << r.voxel << ": "
                  << rec.mesh.triangles.size() << " triangles, " << seconds << " s -> " << o.output << "\n";
    }
    return kSuccess;
}

}  // namespace

void add_reconstruct_command(CLI::App& command, CommandResult& result) {
    auto o = std::make_shared<ReconstructCommandOptions>();
    input_files(command.add_option("INPUT", o->input, "Points: .xyz/.pts (x y z [nx ny nz]), .ply, or a .conf range-scan set"))->required();
    output_file(command.add_option("-o,--output", o->output, "The surface (.stl, .ply, .obj) or the sampled field (.vdb, negative inside)"))
        ->required();
    command.add_option("--voxel", o->rec.sample.voxel, "Voxel size of the sampled field (0: the points' longest side / 256)")
        ->check(kFiniteNonNegative);
    command.add_option("--decimate", o->rec.rbf.decimate.fraction, "Adaptive decimation: the fraction of each leaf's fitted points to remove, in [0, 1)")
        ->check(CLI::Range(0.0, 0.99));
    command.add_option("--seed", o->rec.rbf.decimate.seed, "Seed of the decimation (the same seed repeats the result)");
    command.add_option("--neighbours", o->rec.normals.neighbours, "k of the PCA normals (when the points have none)")
        ->check(CLI::Range(3, 200));
    command.add_option("--leaf", o->rec.rbf.leaf_min, "N1: the partition's leaves hold N1 to 2*N1 points")->check(CLI::Range(8, 500));
    command.add_option("--overlap", o->rec.rbf.overlap, "Overlap of sibling cells, a fraction of the parent's extent")
        ->check(CLI::Range(0.001, 0.45));
    command.add_option("--cluster", o->rec.cluster, "Average the points per cell of this size first (0: the voxel; -1: no averaging)");
    command.add_option("--outliers", o->rec.outlier_factor, "Drop points whose neighbour distance exceeds the median by this factor (0: keep all)")
        ->check(kFiniteNonNegative);
    command.add_option("--min-component", o->rec.min_component,
                       "Drop surface components smaller in volume than this fraction of the largest (0: keep all)")
        ->check(CLI::Range(0.0, 1.0));
    command.add_flag("--ascii", o->ascii, "ASCII STL or PLY");
    command.add_flag("--json", o->json, "Figures as one JSON object on stdout");
    add_common_options(command, o->common);
    add_work_limit_option(command, o->work_limit);
    add_memory_option(command, o->memory, "the points read and the voxel (they are read whole first)");
    command.callback([o, &result] { result.status = run_reconstruct(*o); });
}

}  // namespace vdbmesh::cli
