// A .vdb read by region. The first float grid's topology is read once with OpenVDB's delayed
// loading (leaf buffers stay in the mapped file); read(box) copies the tiles that meet the box
// from that topology and loads the values of only the leaves that meet it. OpenVDB's reader
// can crash on a corrupt file, so every step that decodes the file runs first, or only, in a
// forked child (vdb_probe.h): the topology in a child, then here; the leaf values only in a
// child, which copies them into memory shared with this process, where they arrive as plain
// floats. The file is read once, plus its topology twice. read_vdb() loads every leaf the same
// way, in place (detail::read_first_float_grid()).

#include <sys/mman.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <tuple>
#include <utility>

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

/// Leaves whose values one child loads: 64 MiB of floats.
constexpr std::size_t kLeavesPerChild = (std::size_t{64} << 20) / (Leaf::SIZE * sizeof(float));

/// Memory of this process shared with the children it forks afterwards.
class SharedFloats {
public:
    explicit SharedFloats(std::size_t count) : bytes_(std::max<std::size_t>(count, 1) * sizeof(float)) {
        void* memory = ::mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
        if (memory == MAP_FAILED) throw std::bad_alloc();
        data_ = static_cast<float*>(memory);
    }
    ~SharedFloats() { ::munmap(data_, bytes_); }
    SharedFloats(const SharedFloats&) = delete;
    SharedFloats& operator=(const SharedFloats&) = delete;
    float* data() const { return data_; }

private:
    std::size_t bytes_;
    float* data_ = nullptr;
};

/// Calls @a take(i, values) for each leaf i of @a leaves with its 512 values, loaded from the
/// file by a child per kLeavesPerChild leaves into memory shared with this process (one area,
/// reused).
template <class LeafPtr, class Take>
void load_leaf_values(const std::filesystem::path& path, const std::vector<LeafPtr>& leaves, const Take& take) {
    if (leaves.empty()) return;
    const SharedFloats values(std::min(kLeavesPerChild, leaves.size()) * Leaf::SIZE);
    for (std::size_t first = 0; first < leaves.size(); first += kLeavesPerChild) {
        const std::size_t count = std::min(kLeavesPerChild, leaves.size() - first);
        detail::read_region_in_child(
            path,
            [&] {
                for (std::size_t i = 0; i < count; ++i)  // buffer().data() loads from the file
                    std::memcpy(values.data() + i * Leaf::SIZE, leaves[first + i]->buffer().data(), Leaf::SIZE * sizeof(float));
            },
            count * Leaf::SIZE * sizeof(float));
        for (std::size_t i = 0; i < count; ++i) take(first + i, values.data() + i * Leaf::SIZE);
    }
}

/// Adds to @a out a copy of each leaf of @a leaves, its values loaded by a child.
void add_loaded_leaves(const std::filesystem::path& path, const std::vector<const Leaf*>& leaves, Tree& out) {
    load_leaf_values(path, leaves, [&](std::size_t i, const float* values) {
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
    VdbRegionSource(std::filesystem::path path, openvdb::FloatGrid::Ptr topology)
        : path_(std::move(path)), topology_(std::move(topology)), description_(topology_->copyWithNewTree()) {}

    std::shared_ptr<const openvdb::FloatGrid> description() const override { return description_; }

    /// From the masks only: no leaf buffer is loaded.
    std::vector<NodeWeight> nodes() const override { return node_weights(topology_->tree()); }

    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox& box) const override {
        openvdb::FloatGrid::Ptr grid = topology_->copyWithNewTree();
        grid->setTransform(topology_->transform().copy());
        TreeRegion region{to_bbox(box), &grid->tree(), {}};
        walk_region(topology_->tree(), region);
        add_loaded_leaves(path_, region.leaves, grid->tree());
        return grid;
    }

    std::uint64_t estimated_bytes(const IndexBox& box) const override {
        TreeRegion region{to_bbox(box), nullptr, {}};
        walk_region(topology_->tree(), region);
        return region.bytes();
    }

private:
    std::filesystem::path path_;
    openvdb::FloatGrid::Ptr topology_;  // leaf buffers on disk; never loaded in this process
    std::shared_ptr<const openvdb::FloatGrid> description_;
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
    load_leaf_values(path, leaves, [&](std::size_t i, const float* values) {
        Leaf::Buffer loaded;  // allocated, in memory
        std::memcpy(loaded.data(), values, Leaf::SIZE * sizeof(float));
        leaves[i]->swap(loaded);
    });
    return grid;
}

}  // namespace detail

}  // namespace vdbmesh
