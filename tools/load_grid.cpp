// The input of the grid-consuming subcommands: a .vdb or a scan converted on the fly.

#include "load_grid.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>

#include "vdbmesh/error.h"

namespace vdbmesh::cli {

std::string lowercase_extension(const std::string& path) {
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return extension;
}

std::unique_ptr<VolumeReader> open_scan(const std::vector<std::string>& inputs, const ReadFlags& read) {
    return open_volume(inputs.front(), read.to_read_options({inputs.begin() + 1, inputs.end()}));
}

openvdb::FloatGrid::Ptr convert_timed(VolumeReader& reader, const ConvertOptions& convert,
                                      std::optional<double>& seconds) {
    const auto start = std::chrono::steady_clock::now();
    openvdb::FloatGrid::Ptr grid = convert_to_grid(reader, convert);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return grid;
}

GridInput load_grid(const std::vector<std::string>& inputs, std::optional<double> iso, const ReadFlags& read,
                    const std::string& purpose, ConvertOptions convert) {
    const std::string& input = inputs.front();
    GridInput loaded;
    if (lowercase_extension(input) == ".vdb") {
        if (inputs.size() > 1) throw UsageError("a .vdb input takes no further input files");
        loaded.grid = read_vdb(input);
        const std::optional<double> chosen = iso ? iso : stored_isovalue(*loaded.grid);
        if (!chosen) throw UsageError("--iso: required, " + input + " stores no isovalue");
        loaded.iso = *chosen;
        return loaded;
    }
    if (!iso) throw UsageError("--iso: required to " + purpose + " a scan");
    loaded.iso = *iso;
    convert.iso = *iso;
    auto reader = open_scan(inputs, read);
    loaded.grid = convert_timed(*reader, convert, loaded.convert_seconds);
    return loaded;
}

}  // namespace vdbmesh::cli
