// A .vdb read by region. The first float grid's topology is read once with OpenVDB's delayed
// loading (leaf buffers stay in the mapped file); read(box) copies the tiles that meet the box
// from that topology and loads the values of only the leaves that meet it. OpenVDB's reader
// can crash on a corrupt file, so every step that decodes the file runs first, or only, in a
// forked child (vdb_probe.h): the topology in a child, then here; the leaf values only in
// children (leaf_loading_children.h), which copy them into memory shared with this process,
// where they arrive as plain floats. The file is read once, plus its topology twice. read_vdb() loads every leaf the same
// way, in place (detail::read_first_float_grid()).

#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <string>
#include <tuple>
#include <utility>

#include "leaf_loading_children.h"
#include "leaf_masks.h"
#include "region_walk.h"
#include "vdb_file.h"
#include "vdb_probe.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"

namespace vdbmesh {

namespace {

using detail::region_walk::Leaf;
using detail::region_walk::to_bbox;
using detail::region_walk::Tree;
using detail::region_walk::TreeRegion;
using detail::region_walk::walk_region;
using detail::region_walk::node_weights;

/// Children decoding leaves at once: one per thread this process may use, at most four
/// (16 MiB of shared memory each).
unsigned loading_children() { return static_cast<unsigned>(std::clamp(tbb::this_task_arena::max_concurrency(), 1, 4)); }

/// Adds to @a out a copy of each leaf of @a leaves, its values loaded by @a children.
void add_loaded_leaves(detail::LeafLoadingChildren& children, const std::vector<const Leaf*>& leaves, Tree& out) {
    children.load(leaves, [&](std::size_t i, const float* values) {
        auto* leaf = new Leaf(leaves[i]->origin(), out.background());
        leaf->setValueMask(leaves[i]->getValueMask());
        std::memcpy(leaf->buffer().data(), values, Leaf::SIZE * sizeof(float));
        out.addLeaf(leaf);
    });
}

/// The first float grid of an open file, its leaf buffers left on disk; FormatError listing
/// the grids found when there is none.
openvdb::FloatGrid::Ptr read_first_float_topology(openvdb::io::File& file, const std::filesystem::path& path) {
    std::string found;
    const openvdb::GridPtrVecPtr headers = file.readAllGridMetadata();  // kept: the loop reads through it
    for (const openvdb::GridBase::Ptr& header : *headers) {
        if (header->isType<openvdb::FloatGrid>()) return openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid(header->getName()));
        found += (found.empty() ? "" : ", ") + header->getName() + " (" + header->valueType() + ")";
    }
    throw FormatError(path.string(), "grids", "a float grid", found.empty() ? "no grids" : found);
}

/// Opens @a path for delayed loading and reads its first float grid's topology (the same
/// reading runs first in the probing child). Without a private copy of the file: a copy is
/// what delayed loading makes of files under 500 MB, and reading by region is for big ones.
openvdb::FloatGrid::Ptr read_topology(const std::filesystem::path& path) {
    openvdb::io::File file(path.string());
    file.setCopyMaxBytes(0);
    file.open(/*delayLoad=*/true);
    openvdb::FloatGrid::Ptr grid = read_first_float_topology(file, path);
    file.close();  // the leaf buffers keep the mapping
    return grid;
}

class VdbRegionSource final : public GridRegionSource {
public:
    VdbRegionSource(const std::filesystem::path& path, openvdb::FloatGrid::Ptr topology)
        : topology_(std::move(topology)), description_(topology_->copyWithNewTree()), children_(path, loading_children()) {}

    std::shared_ptr<const openvdb::FloatGrid> description() const override { return description_; }

    /// From the masks only: no leaf buffer is loaded.
    std::vector<NodeWeight> nodes() const override { return node_weights(topology_->tree()); }

    /// From the masks only, as nodes().
    std::vector<LeafMask> active_leaves(const IndexBox& box) const override { return detail::leaf_masks(topology_->tree(), box); }

    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox& box) const override {
        openvdb::FloatGrid::Ptr grid = topology_->copyWithNewTree();
        grid->setTransform(topology_->transform().copy());
        TreeRegion region{to_bbox(box), &grid->tree(), {}};
        walk_region(topology_->tree(), region);
        const std::lock_guard<std::mutex> one_reader(reading_);
        add_loaded_leaves(children_, region.leaves, grid->tree());
        return grid;
    }

    std::uint64_t estimated_bytes(const IndexBox& box) const override {
        TreeRegion region{to_bbox(box), nullptr, {}};
        walk_region(topology_->tree(), region);
        return region.bytes();
    }

private:
    openvdb::FloatGrid::Ptr topology_;  // leaf buffers on disk; never loaded in this process
    std::shared_ptr<const openvdb::FloatGrid> description_;
    mutable std::mutex reading_;
    mutable detail::LeafLoadingChildren children_;
};

/// The topology of @a path's first float grid, its leaf buffers on disk, read first by a child.
openvdb::FloatGrid::Ptr probed_topology(const std::filesystem::path& path) {
    openvdb::initialize();
    detail::require_vdb_header(path);
    detail::probe_vdb_topology_in_child(path, [&] { read_topology(path); });
    openvdb::FloatGrid::Ptr topology;
    try {
        topology = read_topology(path);
    } catch (const FormatError&) {
        throw;
    } catch (const std::exception& e) {  // OpenVDB's own exceptions
        throw FormatError(path.string(), std::string("not a readable .vdb file (") + e.what() + ")");
    }
    return topology;
}

}  // namespace

std::unique_ptr<GridRegionSource> open_vdb_regions(const std::filesystem::path& path) {
    return std::make_unique<VdbRegionSource>(path, probed_topology(path));
}

namespace detail {

openvdb::FloatGrid::Ptr read_first_float_grid(const std::filesystem::path& path) {
    openvdb::FloatGrid::Ptr grid = probed_topology(path);
    // Every leaf's values loaded in place: the buffer on disk swapped for the loaded one.
    std::vector<Leaf*> leaves;
    for (auto leaf = grid->tree().beginLeaf(); leaf; ++leaf) leaves.push_back(&*leaf);
    detail::LeafLoadingChildren children(path, loading_children());
    children.load({leaves.begin(), leaves.end()}, [&](std::size_t i, const float* values) {
        Leaf::Buffer loaded;  // allocated, in memory
        std::memcpy(loaded.data(), values, Leaf::SIZE * sizeof(float));
        leaves[i]->swap(loaded);
    });
    return grid;
}

}  // namespace detail

}  // namespace vdbmesh
