#pragma once
// Private: the values of delay-loaded leaves decoded by child processes (vdb_regions.cpp).
// OpenVDB's reader can crash or loop on a corrupt file, so it decodes only in children; they
// are forked once, when the tree's topology is read, and kept: forking for every region would
// copy the page tables of a parent holding gigabytes, and share its pages copy-on-write again.

#include <openvdb/openvdb.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

namespace vdbmesh::detail {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;

/// Decodes leaf values in up to `children` forked processes at once, each into its own area
/// of memory shared with this process. A child sees the tree as it was when it was forked
/// (on the first load()): the leaves given must have existed then, their buffers on disk.
class LeafLoadingChildren {
public:
    LeafLoadingChildren(std::filesystem::path path, unsigned children);
    ~LeafLoadingChildren();
    LeafLoadingChildren(const LeafLoadingChildren&) = delete;
    LeafLoadingChildren& operator=(const LeafLoadingChildren&) = delete;

    /// Calls @a take(i, values) for each leaf i of @a leaves, in order, with its 512 values.
    /// Throws FormatError naming the file when a child crashes, runs out of memory or time, or
    /// OpenVDB throws (after ending every child: the next load forks afresh).
    void load(const std::vector<const FloatLeaf*>& leaves, const std::function<void(std::size_t, const float*)>& take);

private:
    class Child;
    void fork_children();
    void end_children();

    std::filesystem::path path_;
    unsigned count_;
    std::vector<std::unique_ptr<Child>> children_;
};

}  // namespace vdbmesh::detail
