#include "view_splat_file.h"

#include <chrono>
#include <algorithm>
#include <iostream>
#include <sstream>
#include <utility>

#include "vdbmesh/error.h"
#include "vdbmesh/splats.h"

namespace vdbmesh::cli {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string number_text(double value) {
    std::ostringstream out;
    out.precision(17);
    out << value;
    return out.str();
}

/// UsageError unless @a asked_iso (when given) is @a tree's isovalue; @a instead: what else the user may do.
void require_iso(const SplatTree& tree, const std::filesystem::path& file, std::optional<double> asked_iso,
                 const std::string& instead) {
    if (asked_iso && *asked_iso != tree.iso)
        throw UsageError("--iso " + number_text(*asked_iso) + ": " + file.string() + " holds the splat tree at " +
                         number_text(tree.iso) + "; leave --iso out" + instead);
}

/// The tree in @a file, refused unless it was fitted to the grid of @a id (at @a asked_iso when given).
std::shared_ptr<const SplatTree> read_belonging(const std::filesystem::path& file, const std::filesystem::path& vdb,
                                               const SplatGridId& id, std::optional<double> asked_iso,
                                               std::future<SplatTree> read_ahead) {
    auto tree = std::make_shared<SplatTree>(read_ahead.valid() ? read_ahead.get() : read_splat_file(file));
    const std::string difference = splat_grid_difference(tree->grid, id);
    if (!difference.empty())
        throw Error(file.string() + ": fitted to another grid than " + vdb.string() + " (" + difference +
                    "); remove it to fit " + vdb.filename().string() + " again, or name another --splats file");
    require_iso(*tree, file, asked_iso, ", or name another --splats file");
    return tree;
}

}  // namespace

std::shared_ptr<const ViewSplats> view_splat_file(const std::filesystem::path& file, const std::filesystem::path& vdb,
                                                  const GridRegionSource& regions, std::optional<double> asked_iso,
                                                  std::optional<double> stored_iso, bool quiet,
                                                  std::future<SplatTree> read_ahead) {
    const auto start = std::chrono::steady_clock::now();
    const SplatGridId id = splat_grid_id(vdb, regions);
    auto splats = std::make_shared<ViewSplats>();
    splats->file = file.string();
    if (std::filesystem::exists(file)) {
        splats->tree = read_belonging(file, vdb, id, asked_iso, std::move(read_ahead));
        splats->from_file = true;
    } else {
        const std::optional<double> iso = asked_iso ? asked_iso : stored_iso;
        if (!iso) throw UsageError("--splats: " + vdb.string() + " states no isovalue to fit the splat tree at; give --iso");
        if (!quiet) std::cerr << "vdbmesh view: fitting the splat tree at " << number_text(*iso) << " into " << file.string() << "\n";
        SplatOptions options;
        options.iso = *iso;
        SplatTree tree = build_splat_tree(regions, options);
        tree.grid = id;
        write_splat_file(tree, file);
        splats->tree = std::make_shared<const SplatTree>(std::move(tree));
    }
    splats->seconds = seconds_since(start);
    set_splat_box(*splats);
    if (!quiet)
        std::cerr << "vdbmesh view: " << (splats->from_file ? "read " : "wrote ") << file.string() << ": "
                  << splats->tree->nodes.size() << " splats, " << std::filesystem::file_size(file) << " bytes, "
                  << (splats->from_file ? "read" : "fitted") << " in " << splats->seconds << " s\n";
    return splats;
}

std::shared_ptr<const ViewSplats> view_splats_alone(const std::filesystem::path& file, std::optional<double> asked_iso,
                                                    bool quiet) {
    const auto start = std::chrono::steady_clock::now();
    auto splats = std::make_shared<ViewSplats>();
    splats->file = file.string();
    splats->from_file = true;
    splats->tree = std::make_shared<const SplatTree>(read_splat_file(file));
    require_iso(*splats->tree, file, asked_iso, " (the splats alone are shown at their own isovalue)");
    if (splats->tree->nodes.empty())
        throw Error(file.string() + ": holds no splats (its grid has no surface at " + number_text(splats->tree->iso) + ")");
    splats->seconds = seconds_since(start);
    set_splat_box(*splats);
    if (!quiet)
        std::cerr << "vdbmesh view: read " << file.string() << ": " << splats->tree->nodes.size() << " splats in "
                  << splats->seconds << " s (the splats alone: meshes need the grid they were fitted to)\n";
    return splats;
}

}  // namespace vdbmesh::cli
