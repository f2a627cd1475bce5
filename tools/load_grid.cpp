// The input of the grid-consuming subcommands: a .vdb or a scan converted on the fly.

#include "load_grid.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "vdbmesh/error.h"
#include "vdbmesh/scan_regions.h"
#include "vdbmesh/side_grid.h"

namespace vdbmesh::cli {

std::string lowercase_extension(const std::string& path) {
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return extension;
}

bool is_mesh_file(const std::string& path) {
    const std::string extension = lowercase_extension(path);
    return extension == ".stl" || extension == ".ply" || extension == ".obj";
}

namespace {

std::string number_text(double value) {
    std::ostringstream text;
    text << std::setprecision(10) << value;
    return text.str();
}

/// "600" or "50..150".
std::string isovalues_text(double low, double high) {
    return low == high ? number_text(low) : number_text(low) + ".." + number_text(high);
}

void require_iso_in_band(const std::string& input, const openvdb::FloatGrid& grid, double iso, const std::string& iso_option) {
    const auto band = band_isovalues(grid);
    if (!band || (iso >= band->first && iso <= band->second)) return;
    throw Error(input + ": " + iso_option + " " + number_text(iso) + " lies outside the isovalues its active band was built for (" +
                isovalues_text(band->first, band->second) + "), so the surface there would be wrong; convert the scan again at that isovalue "
                "(or with --iso-range)");
}

}  // namespace

std::unique_ptr<VolumeReader> open_scan(const std::vector<std::string>& inputs, const ReadFlags& read) {
    return open_volume(inputs.front(), read.to_read_options({inputs.begin() + 1, inputs.end()}));
}

openvdb::FloatGrid::Ptr convert_timed(VolumeReader& reader, const ConvertOptions& convert,
                                      std::optional<double>& seconds, Inside inside) {
    const auto start = std::chrono::steady_clock::now();
    openvdb::FloatGrid::Ptr grid = convert_for_side(reader, convert, inside).grid;
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return grid;
}

namespace {

/// The side of the object: @a inside if given, else below for a level set and above otherwise.
Inside side_of(const openvdb::FloatGrid& grid, std::optional<Inside> inside) {
    return inside.value_or(grid.getGridClass() == openvdb::GRID_LEVEL_SET ? Inside::below : Inside::above);
}

/// The isovalue a .vdb is meshed at: @a iso, else the one @a grid stores (0 for a level set).
double vdb_isovalue(const std::string& input, const openvdb::FloatGrid& grid, std::optional<double> iso, const std::string& iso_option) {
    const bool level_set = grid.getGridClass() == openvdb::GRID_LEVEL_SET;
    const std::optional<double> stored = level_set ? std::optional<double>(0.0) : stored_isovalue(grid);
    const std::optional<double> chosen = iso ? iso : stored;
    if (!chosen) throw UsageError(iso_option + ": required, " + input + " stores no isovalue");
    require_iso_in_band(input, grid, *chosen, iso_option);
    return *chosen;
}

/// Refuses what no grid input takes: a mesh file, further inputs after a .vdb, scan flags on a .vdb.
void check_grid_inputs(const std::vector<std::string>& inputs, const ReadFlags& read, const std::string& purpose) {
    const std::string& input = inputs.front();
    if (is_mesh_file(input))
        throw UsageError("expected a .vdb grid or a scan to " + purpose + ", got the mesh " + input + " (a surface already)");
    if (lowercase_extension(input) != ".vdb") return;
    if (inputs.size() > 1) throw UsageError("a .vdb input takes no further input files");
    read.refuse_for("the grid " + input);
}

}  // namespace

GridInput load_grid(const std::vector<std::string>& inputs, std::optional<double> iso, const ReadFlags& read,
                    const std::string& purpose, ConvertOptions convert, const std::string& iso_option,
                    std::optional<Inside> inside) {
    check_grid_inputs(inputs, read, purpose);
    const std::string& input = inputs.front();
    GridInput loaded;
    if (lowercase_extension(input) == ".vdb") {
        loaded.grid = read_vdb(input);
        loaded.level_set = loaded.grid->getGridClass() == openvdb::GRID_LEVEL_SET;
        loaded.iso = vdb_isovalue(input, *loaded.grid, iso, iso_option);
        loaded.inside = side_of(*loaded.grid, inside);
        return loaded;
    }
    if (!iso) throw UsageError(iso_option + ": required to " + purpose + " a scan");
    convert.iso = *iso;
    auto reader = open_scan(inputs, read);
    loaded.grid = convert_timed(*reader, convert, loaded.convert_seconds, inside.value_or(Inside::above));
    loaded.iso = holds_negated_samples(*loaded.grid) ? -*iso : *iso;
    return loaded;
}

GridRegionsInput open_grid_regions(const std::vector<std::string>& inputs, std::optional<double> iso, const ReadFlags& read,
                                   const std::string& purpose, ConvertOptions convert, const std::string& iso_option,
                                   std::optional<Inside> inside) {
    check_grid_inputs(inputs, read, purpose);
    const std::string& input = inputs.front();
    GridRegionsInput opened;
    if (lowercase_extension(input) == ".vdb") {
        opened.source = open_vdb_regions(input);
        const std::shared_ptr<const openvdb::FloatGrid> description = opened.source->description();
        opened.inside = side_of(*description, inside);
        opened.iso = vdb_isovalue(input, *description, iso, iso_option);
        return opened;
    }
    if (!iso) throw UsageError(iso_option + ": required to " + purpose + " a scan");
    opened.iso = *iso;
    opened.inside = inside.value_or(Inside::above);
    convert.iso = *iso;
    opened.source = open_scan_regions([inputs, read] { return std::unique_ptr<SliceReader>(open_scan(inputs, read)); }, convert);
    return opened;
}

Error no_surface_error(const std::string& input, const openvdb::FloatGrid& grid, std::pair<double, double> isovalues,
                       const std::string& output, const std::string& grid_steps) {
    std::optional<std::pair<double, double>> range;
    const auto low = grid.getMetadata<openvdb::DoubleMetadata>(kMetaValueMin);
    const auto high = grid.getMetadata<openvdb::DoubleMetadata>(kMetaValueMax);
    if (low && high) range = std::make_pair(low->value(), high->value());
    if (holds_negated_samples(grid)) {  // said in the scan's terms
        if (range) range = std::make_pair(-range->second, -range->first);
        isovalues = {-isovalues.second, -isovalues.first};
    }
    const std::string values =
        range ? " (its values range from " + number_text(range->first) + " to " + number_text(range->second) + ")" : "";
    const std::string not_written = output.empty() ? "" : "; " + output + " not written";
    const bool values_cross = range && range->first < isovalues.first && range->second > isovalues.second;
    if (!grid_steps.empty() && values_cross)
        return Error(input + ": no surface left after " + grid_steps + " (the values cross iso " +
                     isovalues_text(isovalues.first, isovalues.second) + values + ", so these steps removed it)" + not_written);
    return Error(input + ": no surface at iso " + isovalues_text(isovalues.first, isovalues.second) + values + not_written);
}

}  // namespace vdbmesh::cli
