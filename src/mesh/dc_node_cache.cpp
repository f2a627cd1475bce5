// Nodes' cells shared between the columns of bricks of one process (dc_node_cache.h).

#include "mesh/dc_node_cache.h"

#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

#include "mesh/dc_block_bytes.h"

namespace vdbmesh::detail {

void IfcNodeCache::keep(const IfcCellGrid& built) { keep_where(built, read_later_); }

void IfcNodeCache::keep_every(const IfcCellGrid& built) {
    keep_where(built, [](const openvdb::Coord&) { return true; });
}

void IfcNodeCache::keep_where(const IfcCellGrid& built, const std::function<bool(const openvdb::Coord&)>& wanted) {
    // The blocks of each node, nodes in order (a node's blocks keep their origin order).
    std::map<Key, std::vector<std::size_t>> by_node;
    for (std::size_t b = 0; b < built.origins.size(); ++b) {
        const openvdb::Coord node = ifc_node_of(built.origins[b]);
        if (!has(node) && wanted(node)) by_node[key(node)].push_back(b);
    }
    for (const auto& [node, blocks] : by_node) {
        const std::string bytes = ifc_blocks_bytes(built, blocks);
        kept_[node] = {file_.size(), bytes.size()};
        file_.append(bytes.data(), bytes.size());
    }
}

IfcCellGrid IfcNodeCache::take(const openvdb::CoordBBox& box) const {
    IfcCellGrid taken;
    for (const auto& [node, place] : kept_) {
        const auto& [x, y, z] = node;
        if (!box.isInside(openvdb::Coord(x, y, z))) continue;
        std::string bytes(place.second, '\0');
        file_.read(place.first, bytes.data(), bytes.size());
        append_ifc_blocks(bytes, taken);
    }
    // Nodes' blocks one after another are not in origin order across nodes (x comes first).
    std::vector<std::size_t> order(taken.origins.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return taken.origins[a] < taken.origins[b]; });
    IfcCellGrid sorted;
    sorted.origins.reserve(order.size());
    sorted.blocks.reserve(order.size());
    for (const std::size_t b : order) {
        sorted.origins.push_back(taken.origins[b]);
        sorted.blocks.push_back(std::move(taken.blocks[b]));
    }
    return sorted;
}

}  // namespace vdbmesh::detail
