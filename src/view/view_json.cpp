#include "view/view_json.h"

#include "vdbmesh/shared_splats.h"
#include "vdbmesh/splats.h"

namespace vdbmesh::view {

namespace {

nlohmann::json scan_json(const ViewScan& scan, double initial_iso) {
    nlohmann::json j;
    j["value_min"] = scan.histogram.min;
    j["value_max"] = scan.histogram.max;
    j["histogram"] = scan.histogram.counts;
    j["suggested_iso"] = scan.suggested_iso;
    j["suggested_reason"] = scan.suggested_reason;
    j["initial_iso"] = initial_iso;
    j["coarse_factor"] = scan.coarse_factor;
    return j;
}

}  // namespace

nlohmann::json info_json(const ViewSource& source, std::size_t triangle_budget) {
    nlohmann::json j;
    j["name"] = source.name;
    j["kind"] = source.lattice                           ? "lattice"
                : source.scan || source.prepare_scan     ? "scan"
                : source.splats                          ? "splats"
                : source.labels.empty()                  ? "mesh"
                                                         : "labels";
    j["triangle_budget"] = triangle_budget;
    if (source.scan) j["scan"] = scan_json(*source.scan, source.initial_iso);
    if (source.splats)
        j["splats"] = {{"file", source.splats->file}, {"from_file", source.splats->from_file},
                       {"preview", source.splats->preview},
                       {"nodes", source.splats->tree->nodes.size()}, {"seconds", source.splats->seconds},
                       {"finest_kept", source.splats->tree->finest_kept},
                       {"iso", source.splats->tree->iso}, {"box_min", source.splats->box_min},
                       {"box_max", source.splats->box_max}};
    if (source.lattice) {
        const SharedSplatTree& splats = *source.lattice->splats;
        j["lattice"] = {{"box_min", source.lattice->box_min}, {"box_max", source.lattice->box_max},
                        {"placed", splats.placed.size()}, {"fitted", splats.subtrees.size()},
                        {"represented_nodes", splats.represented_nodes()}, {"seconds", source.lattice->seconds}};
    }
    if (!source.labels.empty()) {
        j["labels"] = nlohmann::json::array();
        for (const ViewLabel& label : source.labels)
            j["labels"].push_back({{"value", label.value}, {"name", label.name}, {"colour", label.colour},
                                   {"first_triangle", label.first_triangle}, {"triangles", label.triangles}});
    }
    return j;
}

}  // namespace vdbmesh::view
