// `vdbmesh info FILE [MORE_PARTS...] [--json]`: describes a scan (header, value statistics from
// one streaming pass, Otsu's threshold as the suggested isovalue; include/vdbmesh/volume_stats.h)
// or a .vdb file (grids, counts, memory, bounding boxes, metadata; describe_vdb_file).
// --json prints exactly one JSON object on stdout. A label map (integer samples with few
// distinct values, or --labels) also lists its labels with voxel counts and names (labels.h).

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli.h"
#include "commands.h"
#include "common_options.h"
#include "label_input.h"
#include "load_grid.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/labels.h"
#include "vdbmesh/read.h"
#include "vdbmesh/shared_tree.h"
#include "vdbmesh/volume_stats.h"

namespace vdbmesh::cli {
namespace {

using Json = nlohmann::ordered_json;

struct InfoOptions {
    std::vector<std::string> inputs;
    bool json = false;
    bool shared = false;
    ReadFlags read;
    LabelFlags label;
    CommonOptions common;
};

std::string join(const std::vector<double>& values, const char* separator) {
    std::ostringstream out;
    for (std::size_t i = 0; i < values.size(); ++i) out << (i ? separator : "") << values[i];
    return out.str();
}

/// The distinct files the samples come from, in reading order.
std::vector<std::string> data_files(const std::vector<DataSegment>& segments) {
    std::vector<std::string> files;
    for (const DataSegment& segment : segments) {
        if (files.empty() || files.back() != segment.path.string()) files.push_back(segment.path.string());
    }
    return files;
}

Json scan_json(const VolumeHeader& h, const std::vector<std::string>& files, const VolumeStats& s) {
    Json j;
    j["file"] = h.path.string();
    j["data_files"] = files;
    j["format"] = h.format;
    j["dims"] = h.dims;
    j["type"] = to_string(h.type);
    j["byte_order"] = to_string(h.byte_order);
    j["spacing"] = h.spacing;
    j["units"] = h.units;
    j["index_to_world"] = h.index_to_world;
    j["value_scale"] = h.value_scale;
    j["value_offset"] = h.value_offset;
    j["samples"] = s.count;
    j["min"] = s.min;
    j["max"] = s.max;
    j["mean"] = s.mean;
    for (std::size_t p = 0; p < kStatsPercentiles.size(); ++p)
        j["percentiles"]["p" + std::to_string(static_cast<int>(kStatsPercentiles[p]))] = s.percentiles[p];
    j["histogram_bin_width"] = s.bin_width;
    j["suggested_iso"] = s.suggested_iso;
    j["suggested_iso_reason"] = s.suggested_reason;
    j["warnings"] = h.warnings;
    return j;
}

void print_scan(const VolumeHeader& h, const std::vector<std::string>& files, const VolumeStats& s, std::ostream& out) {
    out << "file            " << h.path.string() << "\n";
    if (files.size() == 1) out << "data file       " << files.front() << "\n";
    else if (!files.empty()) out << "data files      " << files.size() << ": " << files.front() << " .. " << files.back() << "\n";
    out << "format          " << h.format << "\n"
        << "dims            " << h.dims[0] << " x " << h.dims[1] << " x " << h.dims[2] << " (" << s.count
        << " samples)\n"
        << "type            " << to_string(h.type) << ", " << to_string(h.byte_order) << "-endian\n"
        << "spacing         " << join({h.spacing.begin(), h.spacing.end()}, " x ")
        << (h.units.empty() ? " (units not given)" : " " + h.units) << "\n";
    for (int r = 0; r < 3; ++r)
        out << (r == 0 ? "index to world  " : "                ") << "[" << join({h.index_to_world[r].begin(), h.index_to_world[r].end()}, " ")
            << "]\n";
    out << "value scale     value = raw * " << h.value_scale << " + " << h.value_offset << "\n"
        << "value range     " << s.min << " .. " << s.max << " (mean " << s.mean << ")\n"
        << "percentiles    ";
    for (std::size_t p = 0; p < kStatsPercentiles.size(); ++p) out << " " << kStatsPercentiles[p] << "%: " << s.percentiles[p];
    out << "\nsuggested iso   " << s.suggested_iso << " (" << s.suggested_reason << ")\n";
    for (const std::string& warning : h.warnings) out << "warning         " << warning << "\n";
}

Json grid_json(const GridInfo& g) {
    Json j;
    j["name"] = g.name;
    j["class"] = g.grid_class;
    j["value_type"] = g.value_type;
    j["active_voxels"] = g.active_voxels;
    j["leaf_nodes"] = g.leaf_nodes;
    j["memory_bytes"] = g.memory_bytes;
    if (!g.index_bbox.empty()) {
        j["index_bbox"] = {{g.index_bbox.min().x(), g.index_bbox.min().y(), g.index_bbox.min().z()},
                           {g.index_bbox.max().x(), g.index_bbox.max().y(), g.index_bbox.max().z()}};
        j["world_bbox"] = {{g.world_bbox.min().x(), g.world_bbox.min().y(), g.world_bbox.min().z()},
                           {g.world_bbox.max().x(), g.world_bbox.max().y(), g.world_bbox.max().z()}};
    }
    j["voxel_size"] = {g.voxel_size.x(), g.voxel_size.y(), g.voxel_size.z()};
    for (const auto& [name, value] : g.metadata) j["metadata"][name] = value;
    return j;
}

/// The summary fields every `info --json` has, taken from the grid read_vdb() would pick.
Json vdb_json(const std::string& file, const std::vector<GridInfo>& grids) {
    const auto primary = std::find_if(grids.begin(), grids.end(), [](const GridInfo& g) { return g.value_type == "float"; });
    const GridInfo* g = primary != grids.end() ? &*primary : grids.empty() ? nullptr : &grids.front();
    Json j;
    j["file"] = file;
    j["format"] = "vdb";
    j["grid"] = g ? Json(g->name) : Json();
    const openvdb::Coord dims = g && !g->index_bbox.empty() ? g->index_bbox.dim() : openvdb::Coord(0);
    j["dims"] = {dims.x(), dims.y(), dims.z()};
    j["type"] = g ? Json(g->value_type) : Json();
    j["spacing"] = g ? Json{g->voxel_size.x(), g->voxel_size.y(), g->voxel_size.z()} : Json();
    j["min"] = g && g->value_range ? Json(g->value_range->first) : Json();
    j["max"] = g && g->value_range ? Json(g->value_range->second) : Json();
    j["suggested_iso"] = g && g->isovalue ? Json(*g->isovalue) : Json();
    j["suggested_iso_reason"] = !g || !g->isovalue ? "no isovalue stored in the file"
                                : g->grid_class == "level set" ? "level set: the surface is the zero crossing"
                                                               : "the isovalue stored when the grid was converted";
    j["active_voxels"] = g ? g->active_voxels : 0;
    j["grids"] = Json::array();
    for (const GridInfo& info : grids) j["grids"].push_back(grid_json(info));
    return j;
}

/// A JSON value as text: strings without their quotes.
std::string plain(const Json& value) { return value.is_string() ? value.get<std::string>() : detail::json_text(value); }

void print_vdb(const Json& j, std::ostream& out) {
    out << "file            " << j["file"].get<std::string>() << "\nformat          vdb, " << j["grids"].size()
        << " grid(s)\nsuggested iso   " << detail::json_text(j["suggested_iso"]) << " (" << j["suggested_iso_reason"].get<std::string>()
        << ")\n";
    for (const Json& g : j["grids"]) {
        out << "\ngrid \"" << g["name"].get<std::string>() << "\"\n";
        for (const auto& [key, value] : g.items())
            if (key != "name" && key != "metadata") out << "  " << std::left << std::setw(22) << key << plain(value) << "\n";
        if (g.contains("metadata"))
            for (const auto& [key, value] : g["metadata"].items())
                out << "  " << std::left << std::setw(22) << key << plain(value) << "\n";
    }
}

/// --shared: the grid read_vdb() picks, as a shared tree: nodes stored against represented.
Json shared_json(const std::string& file) {
    const openvdb::FloatGrid::Ptr grid = read_vdb(file);
    const SharedStats s = shared_stats(build_shared_tree(*grid));
    Json j;
    const char* names[3] = {"leaves", "nodes_16", "nodes_32"};
    for (int level = 0; level < 3; ++level) {
        j[names[level]] = {{"stored", s.stored[level]}, {"represented", s.represented[level]}};
    }
    j["tiles"] = s.tiles;
    j["root_entries"] = s.root_entries;
    j["shared_bytes"] = s.shared_bytes;
    j["unshared_bytes"] = s.expanded_bytes;
    j["active_voxels"] = s.active_voxels;
    return j;
}

void print_shared(const Json& j, std::ostream& out) {
    out << "shared tree     stored / represented\n";
    for (const char* name : {"leaves", "nodes_16", "nodes_32"}) {
        out << "  " << std::left << std::setw(14) << name << j[name]["stored"].get<std::uint64_t>() << " / "
            << j[name]["represented"].get<std::uint64_t>() << "\n";
    }
    out << "  " << std::left << std::setw(14) << "tiles" << j["tiles"].get<std::uint64_t>() << "\n";
    out << "  " << std::left << std::setw(14) << "memory" << j["shared_bytes"].get<std::uint64_t>() << " bytes shared, "
        << j["unshared_bytes"].get<std::uint64_t>() << " unshared\n";
}

/// Distinct values up to which an integer scan holding 0 is taken for a label map without
/// --labels (the atlases and TotalSegmentator have 50-120; a CT stored as u8 uses most of its 256 values).
constexpr std::size_t kLabelMapMaxValues = 160;

bool is_integer(SampleType type) { return type != SampleType::f32 && type != SampleType::f64; }

/// The labels of the scan, when it is a label map (always with --labels: an error otherwise).
std::optional<std::vector<LabelCount>> scan_labels(const InfoOptions& o, const VolumeHeader& header) {
    if (!o.label.labels && !is_integer(header.type)) return std::nullopt;
    auto reader = open_scan(o.inputs, o.read);
    Progress progress("counting labels", o.common.quiet);
    auto labels = count_labels(*reader, o.label.labels ? kMaxLabel + 1 : kLabelMapMaxValues, [&](double f) { progress(f); });
    if (!labels && o.label.labels)
        throw FormatError(o.inputs.front(), "--labels: samples", "integer labels 0.." + std::to_string(kMaxLabel),
                          "a sample that is not one");
    // Found without --labels only with a background 0, as label maps and masks have.
    if (labels && !o.label.labels && labels->front().value != 0) return std::nullopt;
    return labels;
}

Json labels_json(const std::vector<LabelCount>& labels, const LabelTable& table, const std::string& table_path) {
    Json j;
    j["label_table"] = table_path.empty() ? Json() : Json(table_path);
    j["labels"] = Json::array();
    for (const LabelCount& label : labels) {
        const auto row = table.find(label.value);
        Json entry = {{"value", label.value}, {"voxels", label.voxels}, {"name", row != table.end() ? Json(row->second.name) : Json()}};
        if (row != table.end() && row->second.color) entry["color"] = *row->second.color;
        j["labels"].push_back(entry);
    }
    return j;
}

void print_labels(const Json& j, std::ostream& out) {
    const std::size_t structures = std::count_if(j["labels"].begin(), j["labels"].end(), [](const Json& l) { return l["value"] != 0; });
    out << "label map       " << structures << " labels besides the background 0"
        << (j["label_table"].is_null() ? ", no name table" : ", names from " + j["label_table"].get<std::string>()) << "\n"
        << "  value      voxels  name\n";
    for (const Json& l : j["labels"])
        out << "  " << std::setw(5) << l["value"].get<std::uint32_t>() << "  " << std::setw(10) << l["voxels"].get<std::uint64_t>()
            << "  " << (l["name"].is_null() ? "" : l["name"].get<std::string>()) << "\n";
}

bool is_vdb(const InfoOptions& o) {
    return o.read.raw_dims.empty() && std::filesystem::path(o.inputs.front()).extension() == ".vdb";
}

int run_info(const InfoOptions& o) {
    const ThreadLimit limit(o.common);
    if (is_vdb(o)) {
        if (o.inputs.size() > 1) throw UsageError("info: a .vdb file takes no further parts");
        Json j = vdb_json(o.inputs.front(), describe_vdb_file(o.inputs.front()));
        if (o.shared) j["shared"] = shared_json(o.inputs.front());
        if (o.json) std::cout << detail::json_text(j) << "\n";
        else {
            print_vdb(j, std::cout);
            if (o.shared) print_shared(j["shared"], std::cout);
        }
        return kSuccess;
    }
    if (o.shared) throw UsageError("--shared: expected a .vdb file, got \"" + o.inputs.front() + "\"");
    auto reader = open_scan(o.inputs, o.read);
    Progress progress("reading", o.common.quiet);
    const VolumeStats stats = compute_volume_stats(*reader, [&](double f) { progress(f); });
    const std::vector<std::string> files = data_files(reader->segments());
    Json labels;
    if (const auto counts = scan_labels(o, reader->header())) {
        std::string table_path;
        const LabelTable table = load_label_table(o.inputs.front(), o.label, table_path);
        labels = labels_json(*counts, table, table_path);
    }
    if (o.json) {
        Json j = scan_json(reader->header(), files, stats);
        if (!labels.is_null()) j.update(labels);
        std::cout << detail::json_text(j) << "\n";
    } else {
        print_scan(reader->header(), files, stats, std::cout);
        if (!labels.is_null()) print_labels(labels, std::cout);
    }
    return kSuccess;
}

}  // namespace

void add_info_command(CLI::App& command, CommandResult& result) {
    auto options = std::make_shared<InfoOptions>();
    InfoOptions& o = *options;
    command.add_option("file", o.inputs, "Scan or .vdb file; further files are the next parts of a split raw scan")
        ->required();
    command.add_flag("--json", o.json, "Print one JSON object instead of text");
    command.add_flag("--shared", o.shared, "A .vdb: distinct nodes stored against nodes represented, per level (shared tree)");
    add_read_flags(command, o.read);
    add_label_flags(command, o.label, "Read the scan as a label map and list its labels (found without it for integer scans with few values)");
    add_common_options(command, o.common);
    command.callback([options, &result] { result.status = run_info(*options); });
}

}  // namespace vdbmesh::cli
