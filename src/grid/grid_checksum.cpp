// Leaves are hashed in parallel into a vector in the tree's own order, then folded serially;
// tiles, background, transform and metadata are folded after them.

#include "grid_checksum.h"

#include <openvdb/tree/LeafManager.h>
#include <tbb/parallel_for.h>

#include <cstring>
#include <string>
#include <vector>

#include "vdbmesh/grid.h"

namespace vdbmesh::detail {

namespace {

/// Folds bytes into a 64-bit state, eight at a time (a multiply-xorshift mix).
class Hasher {
public:
    void add(const void* data, std::size_t size) {
        const auto* bytes = static_cast<const unsigned char*>(data);
        for (; size >= 8; bytes += 8, size -= 8) {
            std::uint64_t word;
            std::memcpy(&word, bytes, 8);
            mix(word);
        }
        std::uint64_t tail = size;
        for (std::size_t i = 0; i < size; ++i) tail = (tail << 8) | bytes[i];
        mix(tail);
    }
    template <typename T>
    void add_value(const T& value) {
        add(&value, sizeof(value));
    }
    std::uint64_t value() const { return state_; }

private:
    void mix(std::uint64_t word) {
        state_ = (state_ ^ word) * 0x9E3779B97F4A7C15ull;
        state_ ^= state_ >> 29;
    }
    std::uint64_t state_ = 0x243F6A8885A308D3ull;
};

std::vector<std::uint64_t> leaf_hashes(const openvdb::FloatTree& tree) {
    const openvdb::tree::LeafManager<const openvdb::FloatTree> leaves(tree);
    std::vector<std::uint64_t> hashes(leaves.leafCount());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, hashes.size()), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
            const auto& leaf = leaves.leaf(i);
            Hasher hasher;
            hasher.add_value(leaf.origin());
            hasher.add(&leaf.getValueMask(), sizeof(leaf.getValueMask()));
            hasher.add(leaf.buffer().data(), sizeof(float) * leaf.size());
            hashes[i] = hasher.value();
        }
    });
    return hashes;
}

}  // namespace

std::uint64_t grid_checksum(const openvdb::FloatGrid& grid) {
    Hasher hasher;
    for (const std::uint64_t leaf : leaf_hashes(grid.tree())) hasher.add_value(leaf);
    auto tiles = grid.tree().cbeginValueAll();
    tiles.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);
    for (; tiles; ++tiles) {
        hasher.add_value(tiles.getCoord());
        hasher.add_value(tiles.getDepth());
        hasher.add_value(*tiles);
        hasher.add_value(tiles.isValueOn());
    }
    hasher.add_value(grid.background());
    const openvdb::Mat4d matrix = grid.transform().baseMap()->getAffineMap()->getMat4();
    hasher.add(matrix.asPointer(), 16 * sizeof(double));
    for (auto meta = grid.beginMeta(); meta != grid.endMeta(); ++meta) {
        // Ours only: OpenVDB's writer adds file_* entries of its own.
        if (meta->first.rfind("vdbmesh_", 0) != 0 || meta->first == kMetaChecksum) continue;
        const std::string entry = meta->first + "=" + meta->second->str();
        hasher.add(entry.data(), entry.size());
    }
    return hasher.value();
}

}  // namespace vdbmesh::detail
