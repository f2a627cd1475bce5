// Intersection-free octree contouring of one column of bricks, one node layer at a time
// (docs/dmc.md, "Bricks"): each node's octree and coarse merge are built once, from the
// layer's samples, and kept while a neighbour still needs them; the blocks of a layer are
// contoured once the layer above is built. So a column holds three node layers of cells and
// samples, whatever its height, and no node is built twice inside it.

#include "mesh/dc_wavefront.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "mesh/dc_block_bytes.h"
#include "mesh/mesh_phases.h"

namespace vdbmesh::detail {

namespace {

constexpr int kLeafVoxels = 8;

/// The lowest z of node layer @a layer.
int layer_z(int layer) { return layer * kNodeVoxels; }

/// @a window and @a layer's blocks together, origins sorted (x, then y, then z) as
/// IfcCellGrid::neighbours() needs. Their origins are disjoint (different z ranges).
IfcCellGrid merge_cells(IfcCellGrid&& window, IfcCellGrid&& layer) {
    IfcCellGrid merged;
    const std::size_t total = window.origins.size() + layer.origins.size();
    merged.origins.reserve(total);
    merged.blocks.reserve(total);
    std::size_t i = 0, j = 0;
    while (i < window.origins.size() || j < layer.origins.size()) {
        const bool from_window = j == layer.origins.size() || (i < window.origins.size() && window.origins[i] < layer.origins[j]);
        IfcCellGrid& from = from_window ? window : layer;
        std::size_t& next = from_window ? i : j;
        merged.origins.push_back(from.origins[next]);
        merged.blocks.push_back(std::move(from.blocks[next]));
        ++next;
    }
    return merged;
}

/// Drops the blocks of @a cells whose origins lie below z = @a z.
void drop_cells_below(IfcCellGrid& cells, int z) {
    std::size_t kept = 0;
    for (std::size_t b = 0; b < cells.origins.size(); ++b) {
        if (cells.origins[b].z() < z) continue;
        cells.origins[kept] = cells.origins[b];
        cells.blocks[kept] = std::move(cells.blocks[b]);
        ++kept;
    }
    cells.origins.resize(kept);
    cells.blocks.resize(kept);
}

}  // namespace

IfcColumnWavefront::IfcColumnWavefront(const GridRegionSource& source, const SampleClassifier& classifier, const MeshOptions& options,
                                       const IfcColumn& column, MeshReport& report, IfcNodeCache* cache, bool release_memory)
    : source_(source), classifier_(classifier), options_(options), column_(column), report_(report), cache_(cache), release_memory_(release_memory) {
    std::shared_ptr<const openvdb::FloatGrid> description = source.description();
    window_ = openvdb::FloatGrid::create(description->background());
    window_->setTransform(description->transform().copy());
}

bool IfcColumnWavefront::in_column(const openvdb::Coord& origin) const {
    return origin.x() >= column_.min_x && origin.x() <= column_.max_x && origin.y() >= column_.min_y && origin.y() <= column_.max_y;
}

void IfcColumnWavefront::read(int z_begin, int z_end) {
    PhaseClock clock;
    // The ring's blocks read samples up to 9 beyond their origins, and their nodes' coarse
    // merges up to one beyond their far faces: a leaf more on each side.
    constexpr int kWiden = kNodeVoxels + kLeafVoxels;
    const IndexBox box{{column_.min_x - kWiden, column_.min_y - kWiden, z_begin},
                       {column_.max_x + 1 + kWiden, column_.max_y + 1 + kWiden, z_end}};
    std::shared_ptr<openvdb::FloatGrid> region = source_.read(box);
    absorb_region(*window_, *region);
    clock.lap(report_, "read");
}

IfcCellGrid IfcColumnWavefront::build_cells(int layer) {
    // The layer's nodes in the column and its ring (block origins, inclusive).
    const openvdb::CoordBBox layer_and_ring({column_.min_x - kNodeVoxels, column_.min_y - kNodeVoxels, layer_z(layer)},
                                            {column_.max_x + kNodeVoxels, column_.max_y + kNodeVoxels, layer_z(layer + 1) - 1});
    IfcOriginFilter build_node;
    if (cache_) build_node = [&](const openvdb::Coord& node) { return !cache_->has(node); };
    IfcCellGrid built = build_ifc_cell_grid(*window_, classifier_, options_, layer_and_ring, report_, build_node);
    if (cache_) {
        PhaseClock clock;
        IfcCellGrid taken = cache_->take(layer_and_ring);  // before keeping this layer's own
        cache_->keep(built);
        built = merge_cells(std::move(built), std::move(taken));
        clock.lap(report_, "cache");
    }
    return built;
}

void IfcColumnWavefront::build(int layer) {
    cells_ = merge_cells(std::move(cells_), build_cells(layer));
    // A block's split reads its 26 neighbours: decide those whose neighbours are all built.
    split_where([&](const openvdb::Coord& o) { return o.z() < layer_z(layer + 1) - kLeafVoxels; });
}

std::string IfcColumnWavefront::prebuild_last_layer(int layer) {
    read(layer_z(layer) - kLeafVoxels, layer_z(layer + 1) + kLeafVoxels);  // what build() reads
    const IfcCellGrid built = build_cells(layer);
    cache_->keep_every(built);
    return ifc_blocks_bytes(built, [&](const openvdb::Coord& o) { return o.z() >= layer_z(layer + 1) - 2 * kLeafVoxels; });
}

void IfcColumnWavefront::take_rows_above(const std::string& rows, int layer) {
    cells_ = merge_cells(std::move(cells_), ifc_blocks_from_bytes(rows));
    // The top block row under them and their bottom row, as the rank above will decide it.
    split_where([&](const openvdb::Coord& o) { return o.z() < layer_z(layer) + kLeafVoxels; });
}

void IfcColumnWavefront::take_rows_below(const std::string& rows, int layer) {
    cells_ = merge_cells(std::move(cells_), ifc_blocks_from_bytes(rows));
    // This layer's bottom block row and their top row, as the rank below decides it; not their
    // second row, whose neighbours below are not here.
    decide_from_z_ = layer_z(layer) - kLeafVoxels;
    split_where([&](const openvdb::Coord& o) { return o.z() < layer_z(layer) + kLeafVoxels; });
    decide_from_z_ = std::numeric_limits<int>::min();
}

void IfcColumnWavefront::split_where(const IfcOriginFilter& decide) {
    PhaseClock clock;
    split_clipped_blocks(cells_, [&](const openvdb::Coord& o) { return o.z() >= decide_from_z_ && decide(o); });
    clock.lap(report_, "split");
}

std::string IfcColumnWavefront::block_rows(int z_begin, int z_end) const {
    return ifc_blocks_bytes(cells_, [&](const openvdb::Coord& o) { return o.z() >= z_begin && o.z() < z_end; });
}

std::vector<IfcNodeOutput> IfcColumnWavefront::contour(int layer) {
    const int z0 = layer_z(layer), z1 = layer_z(layer + 1);
    auto owned = [&](const openvdb::Coord& o) { return o.z() >= z0 && o.z() < z1 && in_column(o); };
    std::vector<IfcBlockOutput> outputs = contour_ifc_cells(*window_, classifier_, options_, cells_, owned, report_);
    return group_ifc_outputs_by_node(cells_.origins, outputs);
}

void IfcColumnWavefront::drop_below(int cells_z, int samples_z) {
    drop_cells_below(cells_, cells_z);
    drop_nodes_below(*window_, samples_z);
    if (release_memory_) release_free_memory();
}

void IfcColumnWavefront::run(int first, int last, const std::function<void(std::vector<IfcNodeOutput>&&)>& consume,
                             IfcColumnBorders* borders) {
    // Building layer s reads samples from one below its bottom to one above its top; the
    // contour of layer s - 1 reads the cells of its blocks and of the blocks next to them (the
    // top block row of layer s - 2, the bottom one of layer s), and the samples of layers
    // s - 2 .. s (a coarse cell next to a block may span a whole node). So the samples come in
    // as: the top leaf row under the first layer built, then per layer its first leaf row
    // (before the layer under it is built) and the rest (after the layer two below is dropped);
    // a contoured layer keeps only its top block row of cells.
    const bool below = borders && borders->below, above = borders && borders->above;
    if (below) decide_from_z_ = layer_z(first) + kLeafVoxels;
    const int start = first - 1;  // built, not contoured: the halo under the column's bricks
    read(layer_z(start) - kLeafVoxels, layer_z(start + 1));
    for (int s = start; s <= last + 1; ++s) {
        read(layer_z(s + 1), layer_z(s + 1) + kLeafVoxels);
        if (s == last + 1 && above) {
            take_rows_above(borders->rows_above(), s);
        } else if (s != start || !below) {
            build(s);
        }
        if (s == first && below) borders->first_layer_built(block_rows(layer_z(s), layer_z(s) + 2 * kLeafVoxels));
        if (s - 1 == first && below) take_rows_below(borders->rows_below(), first);
        if (s - 1 >= first) consume(contour(s - 1));
        drop_below(layer_z(s) - kLeafVoxels, layer_z(s - 1));
        if (s <= last) read(layer_z(s + 1) + kLeafVoxels, layer_z(s + 2));
    }
}

}  // namespace vdbmesh::detail
