// The grid as Dual Marching Cubes reads it (see dmc_grid.h): leaf list, leaf neighbours found
// with probeConstLeaf, and dense sample blocks with a one-voxel ring.

#include "mesh/dmc_grid.h"

#include <tbb/parallel_for.h>

#include <unordered_map>

#include "mesh/edge_crossing.h"
#include "vdbmesh/grid.h"

namespace vdbmesh::detail {

namespace {

/// Range of local coordinates a neighbour block contributes to a SampleBlock.
struct AxisRange {
    int begin, end;
};
AxisRange ring_range(int offset) {
    if (offset < 0) return {-1, 0};
    if (offset > 0) return {kLeafDim, kLeafDim + 1};
    return {0, kLeafDim};
}

}  // namespace

DmcGrid make_dmc_grid(const openvdb::FloatGrid& grid, const MeshOptions& options) {
    DmcGrid result;
    result.grid = &grid;
    result.iso = options.iso;
    result.inside_above = options.inside == Inside::above;
    result.open_boundary = options.open_boundary;
    result.scan_box = stored_scan_box(grid);
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) result.leaves.push_back(&*leaf);

    std::unordered_map<const FloatLeaf*, std::int32_t> index_of;
    index_of.reserve(result.leaves.size());
    for (std::size_t i = 0; i < result.leaves.size(); ++i) index_of.emplace(result.leaves[i], std::int32_t(i));

    result.neighbours.resize(result.leaves.size());
    result.tile_values.resize(result.leaves.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, result.leaves.size()), [&](const auto& range) {
        openvdb::FloatGrid::ConstAccessor accessor = grid.getConstAccessor();
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const openvdb::Coord origin = result.leaves[i]->origin();
            for (int dz = -1; dz <= 1; ++dz) {
                for (int dy = -1; dy <= 1; ++dy) {
                    for (int dx = -1; dx <= 1; ++dx) {
                        const openvdb::Coord block = origin.offsetBy(dx * kLeafDim, dy * kLeafDim, dz * kLeafDim);
                        const FloatLeaf* leaf = accessor.probeConstLeaf(block);
                        result.neighbours[i][neighbour_slot(dx, dy, dz)] = leaf ? index_of.at(leaf) : -1;
                        result.tile_values[i][neighbour_slot(dx, dy, dz)] = leaf ? 0.0f : accessor.getValue(block);
                    }
                }
            }
        }
    });
    return result;
}

void load_sample_block(const DmcGrid& grid, std::size_t leaf, SampleBlock& block) {
    const openvdb::Coord origin = grid.leaves[leaf]->origin();
    block.origin = origin;
    for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
            for (int dz = -1; dz <= 1; ++dz) {
                const AxisRange rx = ring_range(dx), ry = ring_range(dy), rz = ring_range(dz);
                const std::int32_t neighbour = grid.neighbours[leaf][neighbour_slot(dx, dy, dz)];
                if (neighbour >= 0) {
                    const float* data = grid.leaves[neighbour]->buffer().data();
                    for (int x = rx.begin; x < rx.end; ++x) {
                        for (int y = ry.begin; y < ry.end; ++y) {
                            for (int z = rz.begin; z < rz.end; ++z) {
                                const int offset = ((x & 7) << 6) | ((y & 7) << 3) | (z & 7);
                                block.value[SampleBlock::index(x, y, z)] = data[offset];
                            }
                        }
                    }
                } else {
                    // A tile or the background: one value for the whole neighbour block.
                    const float tile = grid.tile_values[leaf][neighbour_slot(dx, dy, dz)];
                    for (int x = rx.begin; x < rx.end; ++x) {
                        for (int y = ry.begin; y < ry.end; ++y) {
                            for (int z = rz.begin; z < rz.end; ++z) block.value[SampleBlock::index(x, y, z)] = tile;
                        }
                    }
                }
            }
        }
    }
    if (grid.scan_box && !grid.scan_box->isInside(openvdb::CoordBBox(origin.offsetBy(-1), origin.offsetBy(kLeafDim)))) {
        const double outside = outside_scan_value(grid.inside_above);
        for (int x = -1; x <= kLeafDim; ++x) {
            for (int y = -1; y <= kLeafDim; ++y) {
                for (int z = -1; z <= kLeafDim; ++z) {
                    if (!grid.scan_box->isInside(origin.offsetBy(x, y, z))) block.value[SampleBlock::index(x, y, z)] = outside;
                }
            }
        }
    }
    for (std::size_t i = 0; i < block.value.size(); ++i) block.inside[i] = grid.inside(block.value[i]);
}

double sample_value(const DmcGrid& grid, std::size_t leaf, int x, int y, int z) {
    const openvdb::Coord voxel = grid.leaves[leaf]->origin().offsetBy(x, y, z);
    if (!grid.in_box(voxel)) return outside_scan_value(grid.inside_above);
    const int slot = neighbour_slot(block_offset(x), block_offset(y), block_offset(z));
    const std::int32_t holder = grid.neighbours[leaf][std::size_t(slot)];
    if (holder < 0) return grid.tile_values[leaf][std::size_t(slot)];
    return grid.leaves[std::size_t(holder)]->buffer().data()[((x & 7) << 6) | ((y & 7) << 3) | (z & 7)];
}

}  // namespace vdbmesh::detail
