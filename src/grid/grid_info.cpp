// Describes grids for `vdbmesh info`: counts, memory and bounding boxes straight from
// OpenVDB's tree queries (openvdb/tree/Tree.h, tools/Count.h).

#include <openvdb/tools/Count.h>

#include "vdb_file.h"
#include "vdbmesh/grid.h"

namespace vdbmesh {

namespace {

/// Min and max of the active values of a scalar grid, when it has any.
template <typename GridT>
std::optional<std::pair<double, double>> active_range(const openvdb::GridBase& grid) {
    const auto* typed = dynamic_cast<const GridT*>(&grid);
    if (!typed || typed->tree().activeVoxelCount() == 0) return std::nullopt;
    const auto range = openvdb::tools::minMax(typed->tree());
    return std::make_pair(static_cast<double>(range.min()), static_cast<double>(range.max()));
}

}  // namespace

GridInfo describe_grid(const openvdb::GridBase& grid) {
    GridInfo info;
    info.name = grid.getName();
    info.grid_class = openvdb::GridBase::gridClassToString(grid.getGridClass());
    info.value_type = grid.valueType();
    info.active_voxels = grid.activeVoxelCount();
    info.leaf_nodes = grid.baseTree().leafCount();
    info.memory_bytes = grid.memUsage();
    info.index_bbox = grid.evalActiveVoxelBoundingBox();
    if (!info.index_bbox.empty()) info.world_bbox = grid.transform().indexToWorld(info.index_bbox);
    info.voxel_size = grid.voxelSize();
    info.value_range = active_range<openvdb::FloatGrid>(grid);
    if (!info.value_range) info.value_range = active_range<openvdb::DoubleGrid>(grid);
    if (const auto* floats = dynamic_cast<const openvdb::FloatGrid*>(&grid)) info.isovalue = stored_isovalue(*floats);
    if (!info.isovalue && grid.getGridClass() == openvdb::GRID_LEVEL_SET) info.isovalue = 0.0;
    for (auto it = grid.beginMeta(); it != grid.endMeta(); ++it) {
        // Name and class are reported above; OpenVDB stores them as metadata too.
        if (it->first == openvdb::GridBase::META_GRID_NAME || it->first == openvdb::GridBase::META_GRID_CLASS)
            continue;
        info.metadata.emplace_back(it->first, it->second->str());
    }
    return info;
}

std::vector<GridInfo> describe_vdb_file(const std::filesystem::path& path) {
    const openvdb::GridPtrVecPtr grids = detail::read_vdb_grids(path);  // kept alive through the loop
    std::vector<GridInfo> infos;
    for (const openvdb::GridBase::Ptr& grid : *grids) infos.push_back(describe_grid(*grid));
    return infos;
}

}  // namespace vdbmesh
