#pragma once
// Private: finding a welded vertex by its key (dual_contouring.cpp). The weld looks up three keys per
// triangle; a binary search over half a million vertices missed the cache about ten times per
// lookup and was half of the weld. Open addressing finds most keys at the first slot; each slot
// holds its key beside the vertex index, so a lookup reads one cache line, which the weld
// prefetches a few triangles ahead.

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace vdbmesh::detail {

class IfcKeyIndex {
public:
    /// Indexes @a keys (unique; a key's index is its position), built in parallel: 16 bytes
    /// per slot, at most three quarters full.
    explicit IfcKeyIndex(const std::vector<std::uint64_t>& keys);
    /// The index of the vertex with @a key, or kMissing.
    std::uint32_t find(std::uint64_t key) const;
    /// Asks the cache for the slot where find(@a key) starts.
    void prefetch(std::uint64_t key) const { __builtin_prefetch(&slots_[first_slot(key)]); }

    static constexpr std::uint32_t kMissing = 0xffffffffu;

private:
    /// No vertex key has all bits set (the kind field of a key is 0 or 1).
    static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);
    struct Slot {
        std::atomic<std::uint64_t> key;
        std::uint32_t index;
    };

    std::size_t first_slot(std::uint64_t key) const {
        // Fibonacci hashing: keys of neighbouring grid edges differ in their low bits, which the
        // multiplication spreads over the high bits taken here.
        return std::size_t((key * 0x9e3779b97f4a7c15ull) >> shift_);
    }

    std::size_t mask_ = 0;
    int shift_ = 63;
    std::unique_ptr<Slot[]> slots_;
};

}  // namespace vdbmesh::detail
