// vdbmesh_decimate_bench: decimate_mesh() against meshoptimizer's meshopt_simplify on the same
// mesh (the bunny CT meshed by DC at error 0), both judged by `vdbmesh check`'s analysis, and
// against DC's own adaptivity (--error), each beside the decimator at its triangle count.
// One JSON object on stdout; figures in bench/README.md.
//
// Usage: vdbmesh_decimate_bench [--keep 0.2] [--errors 0.5,1,1.5,2] [--samples 200000] [--repeat 3]
// --repeat: decimate_mesh() and meshopt_simplify alternately this many times each; the ratio is
// that of the fastest of each (timing under load is noisy). --errors "": no DC rows.

#include <meshoptimizer.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "shared_data_dir.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/process.h"
#include "vdbmesh/read.h"

namespace vdbmesh::bench {
namespace {

using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

openvdb::FloatGrid::Ptr bunny_grid() {
    const auto data = test::shared_data_dir() / "raw_stanford_ct_bunny";
    ReadOptions read;
    read.raw_dims = std::array<std::int64_t, 3>{512, 512, 361};
    read.raw_type = SampleType::i16;
    read.raw_byte_order = ByteOrder::big;
    read.raw_more_files = {data / "bunny_ct_512x512x361_uint16be.part2of2.raw.gz"};
    auto reader = open_volume(data / "bunny_ct_512x512x361_uint16be.part1of2.raw.gz", read);
    ConvertOptions convert;
    convert.iso = 1200.5;
    return convert_to_grid(*reader, convert);
}

/// meshopt_simplify down to @a target triangles, no error limit; the result keeps the input's vertices.
Mesh meshoptimizer_simplify(const Mesh& mesh, std::size_t target) {
    std::vector<unsigned int> indices;
    for (const auto& t : mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
    std::vector<unsigned int> simplified(indices.size());
    const std::size_t count = meshopt_simplify(simplified.data(), indices.data(), indices.size(), &mesh.vertices[0][0],
                                               mesh.vertices.size(), sizeof(mesh.vertices[0]), 3 * target,
                                               std::numeric_limits<float>::max());
    Mesh result;
    result.vertices = mesh.vertices;
    for (std::size_t i = 0; i < count; i += 3) result.triangles.push_back({simplified[i], simplified[i + 1], simplified[i + 2]});
    return result;
}

Json judged(const Mesh& mesh, const Mesh& reference, double seconds, std::size_t samples) {
    const MeshAnalysis r = analyze_mesh(mesh);
    const DistanceReport d = mesh_distance(mesh, reference, samples);
    return {{"seconds", seconds},
            {"triangles", r.triangles},
            {"clean", r.is_clean()},
            {"boundary_edges", r.boundary_edges},
            {"nonmanifold_edges", r.nonmanifold_edges},
            {"nonmanifold_vertices", r.nonmanifold_vertices},
            {"degenerate_faces", r.degenerate_faces},
            {"self_intersecting_pairs", r.self_intersecting_pairs},
            {"volume", r.volume},
            {"hausdorff_to_error0", d.hausdorff},
            {"mean_to_error0", d.mean}};
}

std::vector<double> numbers(const std::string& text) {
    std::vector<double> values;
    std::stringstream in(text);
    for (std::string piece; std::getline(in, piece, ',');) values.push_back(std::stod(piece));
    return values;
}

int run(int argc, char** argv) {
    std::map<std::string, std::string> flags = {
        {"--keep", "0.2"}, {"--errors", "0.5,1,1.5,2"}, {"--samples", "200000"}, {"--repeat", "3"}};
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!flags.count(argv[i])) throw std::invalid_argument(std::string("unknown flag ") + argv[i]);
        flags[argv[i]] = argv[i + 1];
    }
    const double keep = std::stod(flags["--keep"]);
    const auto samples = std::size_t(std::stod(flags["--samples"]));
    const int repeat = std::max(1, std::stoi(flags["--repeat"]));
    openvdb::initialize();
    const openvdb::FloatGrid::Ptr grid = bunny_grid();
    MeshOptions options;
    options.iso = 1200.5;
    const Mesh full = mesh_grid(*grid, options).mesh;
    Json report;
    report["input"] = {{"scan", "bunny CT 512x512x361, iso 1200.5, DC error 0"}, {"triangles", full.triangles.size()}};

    DecimateOptions decimate;
    decimate.keep_fraction = keep;
    DecimateReport counts;
    Mesh ours, theirs;
    double ours_seconds = std::numeric_limits<double>::infinity(), theirs_seconds = ours_seconds;
    for (int run = 0; run < repeat; ++run) {
        auto start = Clock::now();
        ours = decimate_mesh(full, decimate, &counts);
        ours_seconds = std::min(ours_seconds, seconds_since(start));
        start = Clock::now();
        theirs = meshoptimizer_simplify(full, ours.triangles.size());
        theirs_seconds = std::min(theirs_seconds, seconds_since(start));
    }
    report["runs"] = repeat;
    report["time_ratio"] = ours_seconds / theirs_seconds;  // fastest against fastest
    report["vdbmesh_decimate"] = judged(ours, full, ours_seconds, samples);
    report["vdbmesh_decimate"]["rejected"] = {{"topology", counts.rejected_topology},
                                              {"geometry", counts.rejected_geometry},
                                              {"intersection", counts.rejected_intersection}};
    report["meshoptimizer"] = judged(theirs, full, theirs_seconds, samples);
    Clock::time_point start;

    report["dc_error"] = Json::array();
    for (const double error : numbers(flags["--errors"])) {
        options.error = error;
        start = Clock::now();
        const Mesh adaptive = mesh_grid(*grid, options).mesh;
        Json j = judged(adaptive, full, seconds_since(start), samples);
        j["error"] = error;
        // The decimator at the same triangle count, for the comparison at equal counts.
        DecimateOptions same_count;
        same_count.keep_fraction = double(adaptive.triangles.size()) / double(full.triangles.size());
        start = Clock::now();
        const Mesh decimated = decimate_mesh(full, same_count);
        j["decimate_at_same_count"] = judged(decimated, full, seconds_since(start), samples);
        report["dc_error"].push_back(j);
    }
    std::cout << report.dump(2) << "\n";
    return 0;
}

}  // namespace
}  // namespace vdbmesh::bench

int main(int argc, char** argv) {
    try {
        return vdbmesh::bench::run(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "vdbmesh_decimate_bench: " << e.what() << "\n";
        return 1;
    }
}
