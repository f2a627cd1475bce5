// `vdbmesh section INPUT --plane z=42.5 [--planes z=0:100:5] [--normal NX,NY,NZ --offset D]
// [--svg FILE] [--memory SIZE] [--json]`: cross-sections of a closed mesh, or of a scan's
// surface meshed in memory (include/vdbmesh/section.h). With --memory (issue 28): within SIZE
// whatever the input's size, a mesh read as a stream and cut triangle by triangle
// (SectionStream), a scan or .vdb meshed by bricks straight into that stream.

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli.h"
#include "commands.h"
#include "common_options.h"
#include "load_mesh.h"
#include "option_checks.h"
#include "section_svg.h"
#include "write_text_file.h"
#include "vdbmesh/error.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/section.h"

namespace vdbmesh::cli {

namespace {

constexpr std::size_t kMaxPlanes = 100000;  ///< a bound on --planes, against typos like z=0:1e9:1

struct SectionOptions {
    std::vector<std::string> inputs;
    MeshInputOptions input;
    std::vector<std::string> planes, ranges;
    std::string normal;
    double offset = 0;
    std::string svg;
    std::string memory;  ///< --memory SIZE, empty when not given
    bool json = false;
    CommonOptions common;
};

struct NamedPlane {
    std::string label;
    Plane plane;
};

/// "z=42.5" -> axis 2 and the text after '='.
std::pair<int, std::string> split_axis(const std::string& flag, const std::string& text, const std::string& form) {
    const std::size_t equals = text.find('=');
    const std::string axis = text.substr(0, equals);
    if (equals == std::string::npos || axis.size() != 1 || std::string("xyzXYZ").find(axis[0]) == std::string::npos)
        throw UsageError(flag + ": expected " + form + ", got \"" + text + "\"");
    return {int(std::tolower(axis[0]) - 'x'), text.substr(equals + 1)};
}

std::string axis_label(int axis, double value) {
    std::ostringstream label;
    label.precision(9);
    label << char('x' + axis) << "=" << value;
    return label.str();
}

std::vector<NamedPlane> parse_planes(const SectionOptions& o) {
    std::vector<NamedPlane> planes;
    for (const std::string& text : o.planes) {
        const auto [axis, value] = split_axis("--plane", text, "AXIS=VALUE such as z=42.5");
        const double position = parse_number_list("--plane", value).at(0);
        if (value.find(',') != std::string::npos) throw UsageError("--plane: expected one value, got \"" + text + "\"");
        planes.push_back({axis_label(axis, position), axis_plane(axis, position)});
    }
    for (const std::string& text : o.ranges) {
        const auto [axis, range] = split_axis("--planes", text, "AXIS=FIRST:LAST:STEP such as z=0:100:5");
        std::string numbers = range;
        std::replace(numbers.begin(), numbers.end(), ':', ',');
        const std::vector<double> r = parse_number_list("--planes", numbers);
        if (r.size() != 3 || !(r[2] > 0) || r[1] < r[0] || (r[1] - r[0]) / r[2] >= kMaxPlanes)
            throw UsageError("--planes: expected AXIS=FIRST:LAST:STEP with FIRST <= LAST, STEP > 0 and at most " +
                             std::to_string(kMaxPlanes) + " planes, got \"" + text + "\"");
        const auto count = std::size_t(std::floor((r[1] - r[0]) / r[2] * (1 + 1e-12))) + 1;
        for (std::size_t i = 0; i < count; ++i) planes.push_back({axis_label(axis, r[0] + double(i) * r[2]), axis_plane(axis, r[0] + double(i) * r[2])});
    }
    if (!o.normal.empty()) {
        const std::vector<double> n = parse_number_list("--normal", o.normal);
        if (n.size() != 3) throw UsageError("--normal: expected NX,NY,NZ, got \"" + o.normal + "\"");
        const Plane plane = make_plane({n[0], n[1], n[2]}, o.offset);
        planes.push_back({"normal " + o.normal + " offset " + std::to_string(o.offset), plane});
    }
    if (planes.empty()) throw UsageError("section: give at least one plane (--plane z=C, --planes z=A:B:S or --normal)");
    return planes;
}

nlohmann::ordered_json section_json(const std::string& label, const Section& s) {
    nlohmann::ordered_json j;
    j["label"] = label;
    j["plane"] = {{"normal", s.plane.normal}, {"offset", s.plane.offset}};
    j["area"] = s.area;
    j["perimeter"] = s.perimeter;
    j["loops"] = s.loops.size();
    j["holes"] = s.holes();
    j["centroid"] = s.centroid;
    j["u_axis"] = s.u_axis;
    j["v_axis"] = s.v_axis;
    j["second_moments"] = s.second_moments;
    j["loop_list"] = nlohmann::ordered_json::array();
    for (const SectionLoop& loop : s.loops) {
        j["loop_list"].push_back({{"area", loop.area}, {"perimeter", loop.perimeter}, {"depth", loop.depth},
                                  {"parent", loop.parent}, {"points", loop.points.size()}});
    }
    return j;
}

void print_section(const std::string& label, const Section& s, std::ostream& out) {
    out << label << ": area " << s.area << ", perimeter " << s.perimeter << ", " << s.loops.size() << " loops ("
        << s.holes() << " holes), centroid " << s.centroid[0] << " " << s.centroid[1] << " " << s.centroid[2]
        << ", second moments " << s.second_moments[0] << " " << s.second_moments[1] << " " << s.second_moments[2] << "\n";
}

/// section --memory: the mesh as a stream, never held.
std::vector<Section> bounded_sections(const SectionOptions& o, const std::vector<NamedPlane>& named) {
    const std::uint64_t bytes = parse_memory_size("--memory", o.memory);
    std::vector<Plane> planes;
    for (const NamedPlane& p : named) planes.push_back(p.plane);
    if (is_mesh_input(o.inputs, o.input)) return section_mesh_stream(o.inputs.front(), planes, bytes);
    SectionStream stream(o.inputs.front(), std::move(planes), grid_stream_share(bytes, SectionStream::least_bytes(), "section", o.inputs.front()));
    stream_grid_mesh(o.inputs, o.input, "section", bytes, stream);
    return stream.finish();
}

std::vector<Section> whole_sections(const SectionOptions& o, const std::vector<NamedPlane>& planes) {
    const Mesh mesh = load_mesh(o.inputs, o.input, "section");
    std::vector<Section> sections;
    for (const NamedPlane& p : planes) sections.push_back(section_mesh(mesh, p.plane));
    return sections;
}

void run_section(const SectionOptions& o) {
    const ThreadLimit limit(o.common);
    const std::vector<NamedPlane> planes = parse_planes(o);
    const std::vector<Section> sections = o.memory.empty() ? whole_sections(o, planes) : bounded_sections(o, planes);
    std::vector<std::string> labels;
    nlohmann::ordered_json report;
    report["sections"] = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < planes.size(); ++i) {
        labels.push_back(planes[i].label);
        report["sections"].push_back(section_json(planes[i].label, sections[i]));
    }
    if (!o.svg.empty()) write_text_file(o.svg, section_svg(sections, labels));
    if (o.json) {
        std::cout << detail::json_text(report) << "\n";
    } else {
        std::cout.precision(9);
        for (std::size_t i = 0; i < sections.size(); ++i) print_section(labels[i], sections[i], std::cout);
    }
}

}  // namespace

void add_section_command(CLI::App& command, CommandResult& result) {
    auto options = std::make_shared<SectionOptions>();
    input_files(command.add_option("INPUT", options->inputs,
                                   "A closed mesh (.stl, .ply, .obj), or a .vdb or scan meshed in memory (extra files: the parts of a split raw scan)"))
        ->required();
    command.add_option("--plane", options->planes, "A plane AXIS=VALUE, e.g. z=42.5 (world units; repeatable)");
    command.add_option("--planes", options->ranges, "Parallel planes AXIS=FIRST:LAST:STEP, e.g. z=0:100:5 (repeatable)");
    command.add_option("--normal", options->normal, "A plane by its normal NX,NY,NZ (with --offset)");
    command.add_option("--offset", options->offset, "With --normal: the plane's signed distance from the origin along the unit normal")
        ->capture_default_str();
    output_file(command.add_option("--svg", options->svg, "Draw the sections to scale into this SVG file"));
    command.add_flag("--json", options->json, "One JSON object {\"sections\": [...]} instead of text");
    command.add_option("--memory", options->memory,
                       "Section within SIZE (K, M, G) whatever the input's size: a mesh read as a stream and cut triangle by triangle, "
                       "a scan or .vdb meshed by bricks (Marching Cubes at --error 0)");
    add_mesh_input_options(command, options->input);
    add_common_options(command, options->common);
    command.callback([options, &result] {
        run_section(*options);
        result.status = kSuccess;
    });
}

}  // namespace vdbmesh::cli
