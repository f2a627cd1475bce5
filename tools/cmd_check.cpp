// `vdbmesh check MESH [--ref OTHER] [--samples N] [--memory SIZE] [--json]`: validates a mesh
// without repairing anything (include/vdbmesh/analysis.h) and, with --ref, measures its distance
// to another. With --memory the mesh is read as a stream and checked within SIZE whatever its
// size (analyze_mesh_stream(), issue 28): the same figures but the two it cannot count.
// Exit status 0 when the mesh is clean, 3 when it is not, 1 when it cannot be read.

#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli.h"
#include "commands.h"
#include "common_options.h"
#include "report_json.h"
#include "work_limits.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh::cli {

nlohmann::ordered_json report_json(const MeshAnalysis& r) {
    nlohmann::ordered_json j;
    j["clean"] = r.is_clean();
    j["triangles"] = r.triangles;
    j["vertices"] = r.vertices;
    j["unreferenced_vertices"] = r.unreferenced_vertices;
    j["edges"] = r.edges;
    j["boundary_edges"] = r.boundary_edges;
    j["boundary_loops"] = r.boundary_loops;
    j["nonmanifold_edges"] = r.nonmanifold_edges;
    j["nonmanifold_vertices"] = r.nonmanifold_vertices;
    j["misoriented_edges"] = r.misoriented_edges;
    j["degenerate_faces"] = r.degenerate_faces;
    j["repeated_vertex_faces"] = r.repeated_vertex_faces;
    j["zero_area_faces"] = r.zero_area_faces;
    j["self_intersecting_pairs"] = r.self_intersecting_pairs;
    j["components"] = r.components;
    j["euler_characteristic"] = r.euler_characteristic;
    j["genus"] = r.genus;
    j["closed"] = r.closed;
    j["outward"] = r.outward;
    j["negative_components"] = r.negative_components;
    j["area"] = r.area;
    j["volume"] = r.volume;
    j["centroid"] = r.centroid;
    j["inertia"] = r.inertia;
    j["min_angle_deg"] = r.min_angle_deg;
    j["small_angle_share"] = r.small_angle_share;
    return j;
}

nlohmann::ordered_json phases_json(const MeshReport& report) {
    nlohmann::ordered_json phases = nlohmann::ordered_json::array();
    for (const MeshPhase& phase : report.phases) phases.push_back({{"name", phase.name}, {"seconds", phase.seconds}});
    return phases;
}

namespace {

struct CheckOptions {
    std::string mesh, reference, memory;
    std::size_t samples = 100000;
    bool json = false;
    CommonOptions common;
    WorkLimit work_limit;
};

void add_distance(nlohmann::ordered_json& j, const DistanceReport& d, std::size_t samples) {
    j["distance_samples"] = samples;
    j["hausdorff"] = d.hausdorff;
    j["mean_distance"] = d.mean;
    j["rms_distance"] = d.rms;
    j["mean_to_ref"] = d.mean_a_to_b;
    j["mean_from_ref"] = d.mean_b_to_a;
    j["max_to_ref"] = d.max_a_to_b;
    j["max_from_ref"] = d.max_b_to_a;
}

/// The figures a bounded check cannot count: null in JSON, said so in the table.
constexpr const char* kNotCountedBounded[] = {"self_intersecting_pairs", "negative_components"};
constexpr const char* kNotChecked = "not checked in bounded mode";

/// One "name  value" line per field, numbers as JSON writes them.
void print_table(const nlohmann::ordered_json& j, std::ostream& out) {
    for (const auto& [key, value] : j.items()) {
        out << std::left << std::setw(24) << key << (value.is_null() ? kNotChecked : detail::json_text(value)) << "\n";
    }
}

void print_report(const CheckOptions& o, const nlohmann::ordered_json& j) {
    if (o.json) {
        std::cout << detail::json_text(j) << "\n";
    } else {
        std::cout << o.mesh << "\n";
        print_table(j, std::cout);
    }
}

/// check --memory: the mesh as a stream; clean when every figure counted says so.
int run_bounded_check(const CheckOptions& o) {
    if (!o.reference.empty()) throw UsageError("--memory: --ref needs both meshes whole in memory, which --memory does not hold");
    const std::uint64_t bytes = parse_memory_size("--memory", o.memory);
    const ThreadLimit limit(o.common);
    Progress progress("checking", o.common.quiet);
    const StreamCheck check = analyze_mesh_stream(o.mesh, {bytes, 0, [&](double share) { progress(share); }});
    nlohmann::ordered_json j = report_json(check.analysis);
    for (const char* key : kNotCountedBounded) j[key] = nullptr;
    print_report(o, j);
    return check.analysis.is_clean() ? kSuccess : kCheckFailed;
}

int run_check(const CheckOptions& o) {
    if (!o.memory.empty()) return run_bounded_check(o);
    refuse_beyond_work(o.work_limit, "--samples", 2.0 * double(o.samples), "distance queries", 1e-6);
    const ThreadLimit limit(o.common);
    const Mesh mesh = read_mesh(o.mesh);
    const MeshAnalysis report = analyze_mesh(mesh);
    nlohmann::ordered_json j = report_json(report);
    if (!o.reference.empty()) {
        const Mesh reference = read_mesh(o.reference);
        add_distance(j, mesh_distance(mesh, reference, o.samples), o.samples);
    }
    print_report(o, j);
    return report.is_clean() ? kSuccess : kCheckFailed;
}

}  // namespace

void add_check_command(CLI::App& command, CommandResult& result) {
    auto options = std::make_shared<CheckOptions>();
    CheckOptions& o = *options;
    command.add_option("mesh", o.mesh, "Mesh to check (.stl, .ply, .obj)")->required();
    auto* reference = command.add_option("--ref", o.reference, "Reference mesh: adds two-sided Hausdorff, mean and RMS distances");
    command.add_option("--samples", o.samples, "Points sampled on each mesh for --ref")
        ->check(kFinitePositive)
        ->capture_default_str()
        ->needs(reference);
    command.add_option("--memory", o.memory,
                       "Check within SIZE (K, M, G) whatever the mesh's size: read as a stream, edges sorted through temporary "
                       "files in $TMPDIR; self-intersections are not checked");
    command.add_flag("--json", o.json, "One JSON object instead of a table");
    add_common_options(command, o.common);
    add_work_limit_option(command, o.work_limit);
    command.footer("Exit status: 0 clean (closed, manifold, oriented outward, no self-intersections or "
                   "degenerate faces; with --memory, self-intersections not checked), 3 not clean, 1 unreadable, 2 usage "
                   "(a --memory too small: the message names the smallest that works).");
    command.callback([options, &result] { result.status = run_check(*options); });
}

}  // namespace vdbmesh::cli
