// vdbmesh_shared_bench: the figures of issue 14 (shared octrees, periodic lattices).
//   vdbmesh_shared_bench 512    gyroid sheet, period 64 voxels, thickness 4 voxels, 512^3:
//                               distinct leaves vs OpenVDB's leaves; memoised Marching Cubes
//                               (flat and instanced) vs mesh_grid(mc) of the expanded grid,
//                               same triangles after sorting
//   vdbmesh_shared_bench deposit  deposition of 3 voxels: a stepped wafer phantom (exact offset,
//                               OpenVDB's LevelSetFilter::offset, times) and a periodic gyroid
//                               256^3 (shared against plain, times)
//   vdbmesh_shared_bench 4096   the same gyroid at 4096^3 (period 512, thickness 32 voxels):
//                               built and measured (volume, area, components), time and peak
//                               memory; against the 512^3 figures scaled by 8^3 and 8^2; the
//                               components from a plain labelling of one 512^3 period cell
//                               (plain_components_from_crop)
// Each part runs in its own process (peak memory is per process); one JSON line per part on
// stdout. Not a test: it prints timings.

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <sys/resource.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstring>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "vdbmesh/lattice.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/shared_process.h"
#include "vdbmesh/shared_tree.h"

using namespace vdbmesh;
using Json = nlohmann::ordered_json;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

double peak_mb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;
}

double load_average() {
    double load[1] = {0};
    return getloadavg(load, 1) == 1 ? load[0] : -1;
}

LatticeOptions gyroid(int n, int period, int thickness) {
    LatticeOptions o;
    o.kind = LatticeKind::gyroid;
    o.voxel = 1.0;
    o.period = period;
    o.thickness = thickness;
    o.box = {double(n), double(n), double(n)};
    return o;
}

/// The triangles as sorted corner triples (each rotated to start at its smallest corner).
std::vector<std::array<std::array<float, 3>, 3>> sorted_triangles(const Mesh& m) {
    std::vector<std::array<std::array<float, 3>, 3>> t(m.triangles.size());
    for (std::size_t i = 0; i < t.size(); ++i) {
        std::array<std::array<float, 3>, 3> c = {m.vertices[m.triangles[i][0]], m.vertices[m.triangles[i][1]], m.vertices[m.triangles[i][2]]};
        const int k = int(std::min_element(c.begin(), c.end()) - c.begin());
        std::rotate(c.begin(), c.begin() + k, c.end());
        t[i] = c;
    }
    tbb::parallel_sort(t.begin(), t.end());
    return t;
}

double cpu_seconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) + 1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

/// Wall and CPU (user + system, all threads) seconds: each the least over the runs.
struct RunTimes {
    double wall = std::numeric_limits<double>::infinity();
    double cpu = std::numeric_limits<double>::infinity();
};

/// Times @a runs calls of @a f; the last one's result in @a result (the previous one freed
/// before each call, outside the time).
template <class R, class F>
RunTimes min_times(int runs, R& result, F&& f) {
    RunTimes best;
    for (int r = 0; r < runs; ++r) {
        result = R();
        const auto t = std::chrono::steady_clock::now();
        const double c = cpu_seconds();
        R out = f();
        best.wall = std::min(best.wall, seconds_since(t));
        best.cpu = std::min(best.cpu, cpu_seconds() - c);
        result = std::move(out);
    }
    return best;
}

constexpr int kMemoRuns = 5, kPlainRuns = 3;

std::vector<std::array<float, 3>> sorted_vertices(const Mesh& m) {
    std::vector<std::array<float, 3>> v = m.vertices;
    tbb::parallel_sort(v.begin(), v.end());
    return v;
}

Json figures_512() {
    Json j;
    j["part"] = "gyroid 512^3, period 64, thickness 4 voxels";
    j["threads"] = std::thread::hardware_concurrency();
    j["load_before"] = load_average();
    auto t = std::chrono::steady_clock::now();
    const auto field = make_lattice_field(gyroid(512, 64, 4));
    const SharedTree tree = build_shared_tree(*field);
    j["build_s"] = seconds_since(t);
    const SharedStats stats = shared_stats(tree);
    j["unique_leaves"] = stats.stored[0];
    j["unique_nodes1"] = stats.stored[1];
    j["shared_mb"] = double(stats.shared_bytes) / 1e6;
    t = std::chrono::steady_clock::now();
    const auto grid = to_float_grid(tree);
    j["to_grid_s"] = seconds_since(t);
    j["openvdb_leaves"] = grid->tree().leafCount();
    j["openvdb_mb"] = double(grid->tree().memUsage()) / 1e6;
    j["leaf_ratio"] = double(grid->tree().leafCount()) / double(stats.stored[0]);
    t = std::chrono::steady_clock::now();
    j["volume"] = shared_volume(tree);
    j["volume_s"] = seconds_since(t);
    t = std::chrono::steady_clock::now();
    j["area"] = shared_area(tree);
    j["area_s"] = seconds_since(t);
    t = std::chrono::steady_clock::now();
    j["components"] = shared_components(tree);
    j["components_s"] = seconds_since(t);
    t = std::chrono::steady_clock::now();
    j["plain_components"] = plain_components(*grid);
    j["plain_components_s"] = seconds_since(t);
    j["plain_volume"] = plain_volume(*grid);
    // Meshing: the minimum of several runs each (timing noise on a shared machine), the
    // ratios from those minima.
    InstancedMesh inst;
    const RunTimes instanced = min_times(kMemoRuns, inst, [&] { return shared_marching_cubes_instanced(tree); });
    j["instanced_parts"] = inst.parts.size();
    j["instances"] = inst.instances.size();
    Mesh memo;
    const RunTimes flat = min_times(kMemoRuns, memo, [&] { return shared_marching_cubes(tree); });
    MeshOptions options;
    options.method = MeshMethod::mc;
    options.iso = 0.0;
    options.inside = Inside::below;
    Mesh plain;
    const RunTimes unshared = min_times(kPlainRuns, plain, [&] { return mesh_grid(*grid, options).mesh; });
    j["runs"] = {{"memo", kMemoRuns}, {"plain", kPlainRuns}};
    j["memo_mc_instanced_s"] = instanced.wall;
    j["memo_mc_flat_s"] = flat.wall;
    j["plain_mc_s"] = unshared.wall;
    j["speedup_flat"] = unshared.wall / flat.wall;
    j["speedup_instanced"] = unshared.wall / instanced.wall;
    // CPU time (all threads): steadier than wall time when other processes share the cores.
    j["memo_mc_instanced_cpu_s"] = instanced.cpu;
    j["memo_mc_flat_cpu_s"] = flat.cpu;
    j["plain_mc_cpu_s"] = unshared.cpu;
    j["cpu_speedup_flat"] = unshared.cpu / flat.cpu;
    j["cpu_speedup_instanced"] = unshared.cpu / instanced.cpu;
    j["triangles"] = plain.triangles.size();
    j["vertices"] = plain.vertices.size();
    // The same welded mesh: the same vertices and the same triangles (as corner positions).
    // The memoised mesh is freed once sorted (a 40 M-triangle mesh and its sorted triangles
    // take 2 GB).
    j["same_vertices"] = sorted_vertices(memo) == sorted_vertices(plain);
    const auto memo_triangles = sorted_triangles(memo);
    memo = Mesh();
    j["same_triangles"] = memo_triangles == sorted_triangles(plain);
    j["load_after"] = load_average();
    j["peak_mb"] = peak_mb();
    return j;
}

Json figures_4096() {
    Json j;
    j["part"] = "gyroid 4096^3, period 512, thickness 32 voxels";
    j["load_before"] = load_average();
    const auto start = std::chrono::steady_clock::now();
    auto t = start;
    const auto field = make_lattice_field(gyroid(4096, 512, 32));
    const SharedTree tree = build_shared_tree(*field);
    j["build_s"] = seconds_since(t);
    const SharedStats stats = shared_stats(tree);
    j["unique_leaves"] = stats.stored[0];
    j["leaves"] = stats.represented[0];
    j["voxels"] = stats.active_voxels;
    j["shared_mb"] = double(stats.shared_bytes) / 1e6;
    j["expanded_gb"] = double(stats.expanded_bytes) / 1e9;
    t = std::chrono::steady_clock::now();
    j["volume"] = shared_volume(tree);
    j["volume_s"] = seconds_since(t);
    t = std::chrono::steady_clock::now();
    j["area"] = shared_area(tree);
    j["area_s"] = seconds_since(t);
    t = std::chrono::steady_clock::now();
    j["components"] = shared_components(tree);
    j["components_s"] = seconds_since(t);
    j["total_s"] = seconds_since(start);
    j["peak_mb"] = peak_mb();
    // The reference: one 512^3 period cell of the box (voxels 1..512: the box [0, 4096] keeps
    // voxels 1..4095) labelled voxel by voxel, with its versions cut short by the far box faces
    // (the last cells hold 511 voxels), joined cell to cell across the faces between them.
    t = std::chrono::steady_clock::now();
    const CropComponents crop = plain_components_from_crop(*field, {Coord3{1, 1, 1}, Coord3{4095, 4095, 4095}}, 512);
    j["crop_s"] = seconds_since(t);
    j["components_from_crop"] = crop.components;
    j["same_components"] = crop.components == j["components"].get<std::uint64_t>();
    j["component_voxels_from_crop"] = crop.voxels;
    j["crop_components_open"] = crop.crop_components;
    j["crop_components_periodic"] = crop.crop_components_periodic;
    // The 512^3 gyroid's figures, scaled.
    const SharedTree small = build_shared_tree(*make_lattice_field(gyroid(512, 64, 4)));
    const double v512 = shared_volume(small), a512 = shared_area(small);
    j["volume_512_x512"] = v512 * 512;
    j["area_512_x64"] = a512 * 64;
    j["volume_rel_diff"] = j["volume"].get<double>() / (v512 * 512) - 1;
    j["area_rel_diff"] = j["area"].get<double>() / (a512 * 64) - 1;
    j["load_after"] = load_average();
    return j;
}

/// A stepped wafer: a substrate and three steps, repeated @a copies times along x.
struct Wafer final : LeafField {
    int copies = 1;
    explicit Wafer(int n) : copies(n) {}
    static double box_sdf(const double p[3], const double lo[3], const double hi[3]) {
        double outside = 0, inside = -1e300;
        for (int a = 0; a < 3; ++a) {
            const double d = std::max(lo[a] - p[a], p[a] - hi[a]);
            outside += std::max(d, 0.0) * std::max(d, 0.0);
            inside = std::max(inside, d);
        }
        return inside > 0 ? std::sqrt(outside) : inside;
    }
    double sdf(const double p[3]) const {
        double d = 1e300;
        for (int c = 0; c < copies; ++c) {
            const double x0 = 96.0 * c;
            const double boxes[4][2][3] = {{{x0, 0, 0}, {x0 + 96, 96, 8}}, {{x0 + 16, 0, 8}, {x0 + 80, 96, 14}},
                                           {{x0 + 32, 0, 14}, {x0 + 64, 96, 20}}, {{x0 + 44, 0, 20}, {x0 + 52, 96, 26}}};
            for (const auto& b : boxes) d = std::min(d, box_sdf(p, b[0], b[1]));
        }
        return d;
    }
    float background() const override { return 3.0f; }
    double voxel_size() const override { return 1.0; }
    std::array<Coord3, 2> bounds() const override { return {Coord3{-16, -16, -16}, Coord3{96 * copies + 16, 112, 48}}; }
    void evaluate(const Coord3& o, SharedLeaf& leaf) const override {
        for (int i = 0; i < 512; ++i) {
            const double p[3] = {double(o[0] + (i >> 6)), double(o[1] + ((i >> 3) & 7)), double(o[2] + (i & 7))};
            const float v = float(std::clamp(sdf(p), -3.0, 3.0));
            leaf.values[i] = v;
            leaf.set_active(i, v > -3.0f && v < 3.0f);
        }
    }
};

Json figures_deposit() {
    Json j;
    j["part"] = "deposition of 3 voxels";
    j["load_before"] = load_average();
    MeshOptions mc;
    mc.method = MeshMethod::mc;
    mc.inside = Inside::below;
    {
        const Wafer wafer(4);
        const SharedTree in = build_shared_tree(wafer);
        const auto grid = to_float_grid(in);
        auto t = std::chrono::steady_clock::now();
        const SharedTree out = shared_deposit(in, 3.0);
        j["wafer_shared_s"] = seconds_since(t);
        const auto deposited = to_float_grid(out);
        t = std::chrono::steady_clock::now();
        const auto plain = plain_deposit(*grid, 3.0);
        j["wafer_plain_s"] = seconds_since(t);
        j["wafer_same_as_plain"] = plain->activeVoxelCount() == deposited->activeVoxelCount();
        auto theirs = grid->deepCopy();
        t = std::chrono::steady_clock::now();
        openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*theirs);
        filter.offset(-3.0f);
        j["wafer_openvdb_offset_s"] = seconds_since(t);
        double worst = 0, their_worst = 0, disagreement = 0;
        for (const auto& v : mesh_grid(*deposited, mc).mesh.vertices) {
            const double p[3] = {v[0], v[1], v[2]};
            worst = std::max(worst, std::abs(wafer.sdf(p) - 3.0));
        }
        openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> ours(*deposited);
        for (const auto& v : mesh_grid(*theirs, mc).mesh.vertices) {
            const double p[3] = {v[0], v[1], v[2]};
            their_worst = std::max(their_worst, std::abs(wafer.sdf(p) - 3.0));
            disagreement = std::max(disagreement, std::abs(double(ours.wsSample(openvdb::Vec3d(v[0], v[1], v[2])))));
        }
        j["wafer_offset_error_voxels"] = worst;
        j["wafer_openvdb_offset_error_voxels"] = their_worst;
        j["wafer_ours_at_openvdb_surface_voxels"] = disagreement;
        j["wafer_unique_leaves"] = in.leaves.size();
        j["wafer_leaves"] = grid->tree().leafCount();
    }
    {
        const SharedTree in = build_shared_tree(*make_lattice_field(gyroid(256, 64, 4)));
        const auto grid = to_float_grid(in);
        auto t = std::chrono::steady_clock::now();
        const SharedTree out = shared_deposit(in, 3.0);
        j["gyroid256_shared_s"] = seconds_since(t);
        t = std::chrono::steady_clock::now();
        const auto plain = plain_deposit(*grid, 3.0);
        j["gyroid256_plain_s"] = seconds_since(t);
        auto theirs = grid->deepCopy();
        t = std::chrono::steady_clock::now();
        openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*theirs);
        filter.offset(-3.0f);
        j["gyroid256_openvdb_offset_s"] = seconds_since(t);
        j["gyroid256_same_as_plain"] = plain->activeVoxelCount() == to_float_grid(out)->activeVoxelCount();
        j["gyroid256_unique_leaves_after"] = out.leaves.size();
    }
    j["load_after"] = load_average();
    return j;
}

}  // namespace

int main(int argc, char** argv) {
    openvdb::initialize();
    const std::string part = argc > 1 ? argv[1] : "";
    if (part == "512") std::cout << figures_512().dump() << std::endl;
    else if (part == "4096") std::cout << figures_4096().dump() << std::endl;
    else if (part == "deposit") std::cout << figures_deposit().dump() << std::endl;
    else {
        std::cerr << "usage: vdbmesh_shared_bench 512|4096|deposit\n";
        return 2;
    }
    return 0;
}
