// `vdbmesh measure INPUT [--iso V] [--memory SIZE] [--json]`: area, volume, centroid, inertia,
// principal moments and axes, bounding box, genus and components of a mesh file, or of the
// surface of a scan meshed in memory (include/vdbmesh/measure.h). With --labels: per label of a
// label map (label_measure_command.h). With --memory (issue 28): within SIZE whatever the
// input's size, a mesh read as a stream (MeshMeasureStream), a scan or .vdb meshed by bricks
// straight into that stream (stream_grid_mesh(): no temporary mesh file).

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "commands.h"
#include "common_options.h"
#include "label_measure_command.h"
#include "load_mesh.h"
#include "vdbmesh/error.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/measure.h"

namespace vdbmesh::cli {

namespace {

constexpr std::size_t kListedComponents = 10;  ///< components listed in the text output

struct MeasureOptions {
    std::vector<std::string> inputs;
    MeshInputOptions input;
    std::string memory;  ///< --memory SIZE, empty when not given
    bool json = false;
    CommonOptions common;
    LabelMeasureRequest labels;  ///< with --labels (inputs, json, read and common options copied in)
};

nlohmann::ordered_json component_json(const ComponentMeasure& c) {
    return {{"triangles", c.triangles}, {"area", c.area}, {"volume", c.volume}};
}

nlohmann::ordered_json measure_json(const MeshMeasure& m) {
    const MeshAnalysis& r = m.report;
    nlohmann::ordered_json j;
    j["triangles"] = r.triangles;
    j["vertices"] = r.vertices;
    j["closed"] = r.closed;
    j["clean"] = r.is_clean();
    j["area"] = r.area;
    j["volume"] = r.volume;
    j["centroid"] = r.centroid;
    j["inertia"] = r.inertia;
    j["principal_moments"] = m.principal_moments;
    j["principal_axes"] = m.principal_axes;
    j["bounding_box"] = {{"min", m.box_min}, {"max", m.box_max}};
    j["genus"] = r.genus;
    j["components"] = nlohmann::ordered_json::array();
    for (const ComponentMeasure& c : m.components) j["components"].push_back(component_json(c));
    return j;
}

std::ostream& operator<<(std::ostream& out, const std::array<double, 3>& v) {
    return out << v[0] << "  " << v[1] << "  " << v[2];
}

void print_measure(const std::string& input, const MeshMeasure& m, bool bounded, std::ostream& out) {
    const MeshAnalysis& r = m.report;
    out << std::setprecision(9) << input << ": " << r.triangles << " triangles, "
        << (r.is_clean() ? "clean" : r.closed ? "closed but not clean (see vdbmesh check)" : "NOT closed: volume is not meaningful")
        << (bounded ? " (--memory: self-intersections not checked)" : "") << "\n";
    out << "area               " << r.area << "\n"
        << "volume             " << r.volume << "\n"
        << "centroid           " << r.centroid << "\n"
        << "inertia            " << r.inertia[0] << "\n"
        << "                   " << r.inertia[1] << "\n"
        << "                   " << r.inertia[2] << "\n"
        << "principal moments  " << m.principal_moments << "\n";
    for (int k = 0; k < 3; ++k) out << "principal axis " << k << "   " << m.principal_axes[k] << "\n";
    out << "bounding box       " << m.box_min << "  to  " << m.box_max << "\n"
        << "genus              " << r.genus << "\n"
        << "components         " << m.components.size() << " (largest |volume| first: volume, area, triangles)\n";
    for (std::size_t i = 0; i < std::min(m.components.size(), kListedComponents); ++i) {
        const ComponentMeasure& c = m.components[i];
        out << "  " << std::setw(5) << i << "  " << c.volume << "  " << c.area << "  " << c.triangles << "\n";
    }
    if (m.components.size() > kListedComponents) {
        out << "  ... " << m.components.size() - kListedComponents << " more (--json lists all)\n";
    }
}

/// measure --memory: the mesh as a stream, never held.
MeshMeasure bounded_measure(const MeasureOptions& o) {
    const std::uint64_t bytes = parse_memory_size("--memory", o.memory);
    Progress progress("measuring", o.common.quiet);
    const StreamCheckOptions options{bytes, 0, [&](double share) { progress(share); }};
    if (is_mesh_input(o.inputs, o.input)) return measure_mesh_stream(o.inputs.front(), options);
    const StreamCheckOptions share{grid_stream_share(bytes, MeshMeasureStream::least_bytes(), "measure", o.inputs.front()), 0,
                                   options.progress};
    MeshMeasureStream stream(o.inputs.front(), share);
    stream_grid_mesh(o.inputs, o.input, "measure", bytes, stream);
    return stream.finish();
}

void run_measure(MeasureOptions& o) {
    if (o.labels.label.labels) {
        LabelMeasureRequest& request = o.labels;
        request.inputs = o.inputs, request.json = o.json, request.read = o.input.read, request.common = o.common;
        if (request.json && request.csv) throw UsageError("--csv and --json: expected one of them");
        if (!o.memory.empty()) throw UsageError("--memory: not with --labels (each label's mesh is made and measured in memory)");
        return run_label_measure(request);
    }
    if (o.labels.csv) throw UsageError("--csv: only with --labels");
    const ThreadLimit limit(o.common);
    const MeshMeasure measure = o.memory.empty() ? measure_mesh(load_mesh(o.inputs, o.input, "measure")) : bounded_measure(o);
    if (o.json) {
        std::cout << detail::json_text(measure_json(measure)) << "\n";
    } else {
        print_measure(o.inputs.front(), measure, !o.memory.empty(), std::cout);
    }
}

}  // namespace

void add_measure_command(CLI::App& command, CommandResult& result) {
    auto options = std::make_shared<MeasureOptions>();
    command.add_option("INPUT", options->inputs,
                       "A mesh (.stl, .ply, .obj), or a .vdb or scan meshed in memory (extra files: the parts of a split raw scan)")
        ->required();
    add_mesh_input_options(command, options->input);
    command.add_option("--memory", options->memory,
                       "Measure within SIZE (K, M, G) whatever the input's size: a mesh read as a stream, a scan or .vdb meshed by "
                       "bricks (Marching Cubes at --error 0); sums sorted and spooled through temporary files in $TMPDIR; self-intersections "
                       "not checked (\"clean\" counts the rest)");
    command.add_flag("--json", options->json, "One JSON object instead of a table");
    add_label_flags(command, options->labels.label, "A label map: measure each label's mesh (all, or a list like 3,5,10-12)");
    command.add_flag("--csv", options->labels.csv, "--labels: CSV instead of a table");
    add_common_options(command, options->common);
    command.callback([options, &result] {
        run_measure(*options);
        result.status = kSuccess;
    });
}

}  // namespace vdbmesh::cli
