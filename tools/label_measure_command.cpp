// `vdbmesh measure --labels` (label_measure_command.h).

#include "label_measure_command.h"

#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "vdbmesh/json_text.h"

namespace vdbmesh::cli {
namespace {

std::string name_of(const LabelTable& table, std::uint32_t value) {
    const auto row = table.find(value);
    return row != table.end() ? row->second.name : "";
}

/// RFC 4180: a field with a comma, quote or line break is quoted, its quotes doubled.
std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

double relative_error(const LabelMeasure& m) { return m.voxel_volume > 0 ? (m.volume - m.voxel_volume) / m.voxel_volume : 0.0; }

}  // namespace

void run_label_measure(const LabelMeasureRequest& request) {
    LabelMeshOptions options;
    options.labels = parse_label_list(request.label.labels->empty() ? "all" : *request.label.labels);
    const ThreadLimit limit(request.common);
    Progress progress("measuring labels", request.common.quiet);
    const LabelInput input = load_label_input(request.inputs, request.read, request.label);
    const LabelSurface surface = mesh_labels(input.volume, options, [&](double f) { progress(f); });
    const std::vector<LabelMeasure> measures = measure_labels(surface, input.volume);
    if (request.json) {
        nlohmann::ordered_json j;
        j["file"] = request.inputs.front();
        j["label_table"] = input.table_path.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(input.table_path);
        j["units"] = input.volume.header.units;
        j["labels"] = nlohmann::ordered_json::array();
        for (const LabelMeasure& m : measures)
            j["labels"].push_back({{"value", m.value}, {"name", name_of(input.table, m.value)}, {"voxels", m.voxels},
                                   {"voxel_volume", m.voxel_volume}, {"volume", m.volume}, {"volume_error", relative_error(m)},
                                   {"area", m.area}, {"centroid", m.centroid}, {"triangles", m.triangles}});
        std::cout << detail::json_text(j) << "\n";
        return;
    }
    std::cout << std::setprecision(9);
    if (request.csv) {
        std::cout << "value,name,voxels,voxel_volume,volume,volume_error,area,centroid_x,centroid_y,centroid_z\n";
        for (const LabelMeasure& m : measures)
            std::cout << m.value << "," << csv_field(name_of(input.table, m.value)) << "," << m.voxels << "," << m.voxel_volume << ","
                      << m.volume << "," << relative_error(m) << "," << m.area << "," << m.centroid[0] << "," << m.centroid[1] << ","
                      << m.centroid[2] << "\n";
        return;
    }
    std::cout << request.inputs.front() << ": " << measures.size() << " labels (volumes in "
              << (input.volume.header.units.empty() ? "world units" : input.volume.header.units) << "^3)\n"
              << std::setw(6) << "value" << "  " << std::left << std::setw(28) << "name" << std::right << std::setw(10) << "voxels"
              << std::setw(14) << "volume" << std::setw(9) << "error%" << std::setw(14) << "area" << "  centroid\n";
    for (const LabelMeasure& m : measures)
        std::cout << std::setprecision(6) << std::setw(6) << m.value << "  " << std::left << std::setw(28) << name_of(input.table, m.value)
                  << std::right << std::setw(10) << m.voxels << std::setw(14) << m.volume << std::setw(9) << std::fixed << std::setprecision(3)
                  << 100 * relative_error(m) << std::defaultfloat << std::setprecision(6) << std::setw(14) << m.area << "  " << m.centroid[0] << " "
                  << m.centroid[1] << " " << m.centroid[2] << "\n";
}

}  // namespace vdbmesh::cli
