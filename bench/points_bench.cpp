// vdbmesh_points_bench: point clouds to surfaces (issue 13). The Stanford bunny range scans
// reconstructed and measured against bun_zipper.ply (every reference vertex to our surface,
// in % of the reference's bounding-box diagonal), judged by analyze_mesh(); the same with
// --decimate 0.3; the torus scaling (1e5 and 1e6 points). One JSON object on stdout.
//
// Usage: vdbmesh_points_bench [bunny] [decimate] [torus] [--voxel V]   (default: all)
// The environment variables KEEP_ALL, CLUSTER, BAND, OFF_EVERY, LEAF override options (experiments).

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <numeric>
#include <random>
#include <string>

#include "shared_data_dir.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/points.h"
#ifdef VDBMESH_BENCH_CGAL_POISSON
#include "poisson_anchor.h"
#endif

namespace vdbmesh::bench {
namespace {

using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

struct Accuracy {
    double max = 0, mean = 0, diagonal = 0;
};

/// Every vertex of @a reference to the surface @a mesh, in % of the reference's box diagonal.
Accuracy accuracy(const Mesh& reference, const Mesh& mesh) {
    std::vector<std::uint32_t> all(mesh.triangles.size());
    std::iota(all.begin(), all.end(), 0u);
    const detail::TriangleBvh bvh(mesh, all);
    std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const auto& v : reference.vertices)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], double(v[a])), hi[a] = std::max(hi[a], double(v[a]));
    Accuracy r;
    r.diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    std::vector<double> d(reference.vertices.size());
    for (std::size_t i = 0; i < d.size(); ++i) {
        const auto& v = reference.vertices[i];
        d[i] = std::sqrt(bvh.closest_point(detail::Point3{v[0], v[1], v[2]}).distance_squared);
    }
    double sum = 0;
    for (double x : d) sum += x, r.max = std::max(r.max, x);
    r.mean = 100.0 * sum / double(d.size()) / r.diagonal;
    r.max = 100.0 * r.max / r.diagonal;
    return r;
}

/// Our surface's vertices to @a reference: the largest, the mean and the 99th percentile, in %
/// of @a diagonal (bun_zipper has open holes under the bunny, which we close: the largest
/// distances are there).
Json reverse_accuracy(const Mesh& mesh, const Mesh& reference, double diagonal) {
    std::vector<std::uint32_t> all(reference.triangles.size());
    std::iota(all.begin(), all.end(), 0u);
    const detail::TriangleBvh bvh(reference, all);
    std::vector<double> d(mesh.vertices.size());
    for (std::size_t i = 0; i < d.size(); ++i) {
        const auto& v = mesh.vertices[i];
        d[i] = 100.0 * std::sqrt(bvh.closest_point(detail::Point3{v[0], v[1], v[2]}).distance_squared) / diagonal;
    }
    if (const char* dump = std::getenv("DUMP_FAR")) {
        FILE* f = std::fopen(dump, "a");
        std::fprintf(f, "# mesh\n");
        for (std::size_t i = 0; i < d.size(); ++i)
            if (d[i] > 1.0) std::fprintf(f, "%g %g %g %g\n", mesh.vertices[i][0], mesh.vertices[i][1], mesh.vertices[i][2], d[i]);
        std::fclose(f);
    }
    double sum = 0;
    for (double x : d) sum += x;
    std::sort(d.begin(), d.end());
    Json j;
    j["max_percent"] = d.empty() ? 0.0 : d.back();
    j["mean_percent"] = d.empty() ? 0.0 : sum / double(d.size());
    j["p99_percent"] = d.empty() ? 0.0 : d[d.size() * 99 / 100];
    return j;
}

Json run_bunny(double voxel, double decimate, const Mesh& reference) {
    const auto conf = test::shared_data_dir() / "pointcloud_stanford_bunny_scans" / "data" / "bun.conf";
    const auto start = Clock::now();
    PointCloud cloud = read_points(conf);
    const double read_seconds = seconds_since(start);
    ReconstructOptions options;
    options.sample.voxel = voxel;
    options.decimate = decimate;
    if (std::getenv("KEEP_ALL")) options.min_component = 0;
    if (const char* c = std::getenv("CLUSTER")) options.cluster = std::stod(c);
    if (const char* c = std::getenv("BAND")) options.sample.band = std::stod(c);
    if (const char* c = std::getenv("OFF_EVERY")) options.rbf.off_every = std::stoi(c);
    if (const char* c = std::getenv("LEAF")) options.rbf.leaf_min = std::stoi(c);
    const Reconstruction rec = reconstruct(std::move(cloud), options);
    const double seconds = seconds_since(start);
    const MeshAnalysis analysis = analyze_mesh(rec.mesh);
    if (const char* dump = std::getenv("DUMP_MESH")) write_mesh(rec.mesh, dump, MeshWriteOptions{true, false});
    const Accuracy acc = accuracy(reference, rec.mesh);
    Json j;
    j["decimate"] = decimate;
    j["voxel"] = rec.report.voxel;
    j["input_points"] = rec.report.input_points;
    j["outliers"] = rec.report.outliers;
    j["used_points"] = rec.report.used_points;
    j["leaves"] = rec.report.leaves;
    j["triangles"] = rec.mesh.triangles.size();
    j["dropped_components"] = rec.report.dropped_components;
    j["fallbacks"] = rec.report.mesh_fallbacks;
    j["clean"] = analysis.is_clean();
    j["closed"] = analysis.closed;
    j["self_intersecting_pairs"] = analysis.self_intersecting_pairs;
    j["boundary_edges"] = analysis.boundary_edges;
    j["nonmanifold_edges"] = analysis.nonmanifold_edges;
    j["nonmanifold_vertices"] = analysis.nonmanifold_vertices;
    j["misoriented_edges"] = analysis.misoriented_edges;
    j["degenerate_faces"] = analysis.degenerate_faces;
    j["volume"] = analysis.volume;
    j["seconds"] = seconds;
    j["read_seconds"] = read_seconds;
    Json phases;
    for (const auto& [name, s] : rec.report.phases) phases[name] = s;
    j["phases"] = phases;
    j["max_percent_of_diagonal"] = acc.max;
    j["mean_percent_of_diagonal"] = acc.mean;
    j["reference_diagonal"] = acc.diagonal;
    j["ours_to_reference"] = reverse_accuracy(rec.mesh, reference, acc.diagonal);
    return j;
}

/// @a count points on the torus R = 1, r = 0.4 (uniform by area), no normals.
PointCloud torus_points(std::size_t count, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> angle(0, 2 * M_PI), w(0, 1.4);
    PointCloud c;
    c.points.reserve(count);
    while (c.points.size() < count) {
        const double a = angle(rng), b = angle(rng);
        if (w(rng) > 1 + 0.4 * std::cos(b)) continue;
        c.points.push_back({(1 + 0.4 * std::cos(b)) * std::cos(a), (1 + 0.4 * std::cos(b)) * std::sin(a), 0.4 * std::sin(b)});
    }
    return c;
}

Json run_torus(std::size_t count, double cluster) {
    ReconstructOptions options;
    options.sample.voxel = 2.8 / 256;
    options.cluster = cluster;
    PointCloud cloud = torus_points(count, 5);
    const auto start = Clock::now();
    const Reconstruction rec = reconstruct(std::move(cloud), options);
    Json j;
    j["points"] = count;
    j["cluster"] = cluster;
    j["used_points"] = rec.report.used_points;
    j["leaves"] = rec.report.leaves;
    j["triangles"] = rec.mesh.triangles.size();
    j["seconds"] = seconds_since(start);
    Json phases;
    for (const auto& [name, sec] : rec.report.phases) phases[name] = sec;
    j["phases"] = phases;
    return j;
}

#ifdef VDBMESH_BENCH_CGAL_POISSON
/// CGAL's Poisson on the same scans with the same normals (PCA, towards each scanner).
Json run_poisson(const Mesh& reference) {
    const auto conf = test::shared_data_dir() / "pointcloud_stanford_bunny_scans" / "data" / "bun.conf";
    const auto start = Clock::now();
    PointCloud cloud = read_points(conf);
    remove_outliers(cloud, 8, 4.0);
    remove_small_clusters(cloud);
    estimate_normals(cloud);
    const double normals_seconds = seconds_since(start);
    const Mesh mesh = cgal_poisson(cloud);
    const double seconds = seconds_since(start);
    const MeshAnalysis analysis = analyze_mesh(mesh);
    const Accuracy acc = accuracy(reference, mesh);
    Json j;
    j["method"] = "CGAL::poisson_surface_reconstruction_delaunay, normals by vdbmesh (PCA k=16, towards each scanner)";
    j["triangles"] = mesh.triangles.size();
    j["clean"] = analysis.is_clean();
    j["closed"] = analysis.closed;
    j["seconds"] = seconds;
    j["normals_seconds"] = normals_seconds;
    j["max_percent_of_diagonal"] = acc.max;
    j["mean_percent_of_diagonal"] = acc.mean;
    j["ours_to_reference"] = reverse_accuracy(mesh, reference, acc.diagonal);
    return j;
}
#endif

}  // namespace
}  // namespace vdbmesh::bench

int main(int argc, char** argv) {
    using namespace vdbmesh;
    using namespace vdbmesh::bench;
    std::vector<std::string> parts;
    double voxel = 0.0005;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--voxel") && i + 1 < argc) voxel = std::stod(argv[++i]);
        else parts.emplace_back(argv[i]);
    }
    auto want = [&](const std::string& p) { return parts.empty() || std::find(parts.begin(), parts.end(), p) != parts.end(); };
    Json out;
    try {
        const auto zipper = test::shared_data_dir() / "pointcloud_stanford_bunny_scans" / "reconstruction" / "bun_zipper.ply";
        if (want("line")) {
        PointCloud cloud = read_points(test::shared_data_dir() / "pointcloud_stanford_bunny_scans" / "data" / "bun.conf");
        remove_outliers(cloud, 8, 4.0);
        std::cout << "clusters removed " << remove_small_clusters(cloud) << "\n";
        estimate_normals(cloud);
        const RbfField field(cloud);
        for (double x = -0.12; x < -0.05; x += 0.002) {
            const Vec3d p{x, 0.1, 0.0};
            std::cout << x << " f " << field.value(p) << " d " << field.distance_to_points(p) << "\n";
        }
        return 0;
    }
    if (want("bunny") || want("decimate")) {
            const Mesh reference = read_mesh(zipper);
            if (want("bunny")) out["bunny"] = run_bunny(voxel, 0.0, reference);
            if (want("decimate")) out["bunny_decimate_0.3"] = run_bunny(voxel, 0.3, reference);
#ifdef VDBMESH_BENCH_CGAL_POISSON
            if (want("bunny")) {
                out["cgal_poisson"] = run_poisson(reference);
                out["time_ratio_vs_cgal_poisson"] = out["bunny"]["seconds"].get<double>() / out["cgal_poisson"]["seconds"].get<double>();
            }
#endif
        }
        if (want("torus")) {
            // The default pipeline (points averaged per voxel first) and the RBF on every point.
            for (const double cluster : {0.0, -1.0}) {
                const Json small = run_torus(100000, cluster), large = run_torus(1000000, cluster);
                Json t;
                t["1e5"] = small;
                t["1e6"] = large;
                t["ratio"] = large["seconds"].get<double>() / small["seconds"].get<double>();
                out[cluster < 0 ? "torus_every_point" : "torus_default"] = t;
            }
        }
    } catch (const std::exception& e) {
        std::cerr << "vdbmesh_points_bench: " << e.what() << "\n";
        return 1;
    }
    std::cout << out.dump(2) << "\n";
    return 0;
}
