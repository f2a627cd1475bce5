#pragma once
// Private: nodes' cells that one column of bricks built and a later column of the same process
// reads again (as its own nodes or its ring's), kept in a temporary file so that no node is
// built twice in one process (dc_wavefront.cpp; docs/dmc.md, "Bricks").

#include <openvdb/openvdb.h>

#include <cstdint>
#include <functional>
#include <map>
#include <tuple>
#include <utility>

#include "mesh/dual_contouring.h"
#include "vdbmesh/temp_file.h"

namespace vdbmesh::detail {

class IfcNodeCache {
public:
    /// @a read_later(node): whether a column after the current one reads node @a node.
    explicit IfcNodeCache(std::function<bool(const openvdb::Coord& node)> read_later) : read_later_(std::move(read_later)) {}

    /// Whether node @a node's cells are kept (built by an earlier column).
    bool has(const openvdb::Coord& node) const { return kept_.count(key(node)) != 0; }
    /// Keeps the nodes of @a built (cells as built, before any split) that a later column reads.
    void keep(const IfcCellGrid& built);
    /// Keeps every node of @a built not kept yet (a layer built ahead of its turn).
    void keep_every(const IfcCellGrid& built);
    /// The kept nodes' cells among the blocks with origins in @a box, origins sorted.
    IfcCellGrid take(const openvdb::CoordBBox& box) const;

private:
    using Key = std::tuple<int, int, int>;
    static Key key(const openvdb::Coord& c) { return {c.x(), c.y(), c.z()}; }
    void keep_where(const IfcCellGrid& built, const std::function<bool(const openvdb::Coord&)>& wanted);

    std::function<bool(const openvdb::Coord&)> read_later_;
    TempFile file_{"for the nodes columns share"};
    std::map<Key, std::pair<std::uint64_t, std::uint64_t>> kept_;  ///< node -> bytes' offset, size
};

}  // namespace vdbmesh::detail
