#include "mesh/ifc_key_index.h"

#include "vdbmesh/huge_pages.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace vdbmesh::detail {

IfcKeyIndex::IfcKeyIndex(const std::vector<IfcVertex>& vertices) : vertices_(vertices) {
    int bits = 1;
    while ((std::size_t(1) << bits) < 2 * vertices.size()) ++bits;
    const std::size_t slot_count = std::size_t(1) << bits;
    mask_ = slot_count - 1;
    shift_ = 64 - bits;
    slots_.reset(new std::atomic<std::uint32_t>[slot_count]);
    advise_huge_pages(slots_.get(), slot_count * sizeof(std::atomic<std::uint32_t>));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, slot_count), [&](const auto& range) {
        for (std::size_t s = range.begin(); s != range.end(); ++s) slots_[s].store(kMissing, std::memory_order_relaxed);
    });
    // Which vertex lands in which slot depends on the threads' order; what find() returns
    // does not (keys are unique).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertices.size()), [&](const auto& range) {
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            for (std::size_t s = first_slot(vertices[v].key);; s = (s + 1) & mask_) {
                std::uint32_t empty = kMissing;
                if (slots_[s].compare_exchange_strong(empty, std::uint32_t(v), std::memory_order_relaxed)) break;
            }
        }
    });
}

std::size_t IfcKeyIndex::first_slot(std::uint64_t key) const {
    // Fibonacci hashing: keys of neighbouring grid edges differ in their low bits, which the
    // multiplication spreads over the high bits taken here.
    return std::size_t((key * 0x9e3779b97f4a7c15ull) >> shift_);
}

std::uint32_t IfcKeyIndex::find(std::uint64_t key) const {
    for (std::size_t s = first_slot(key);; s = (s + 1) & mask_) {
        const std::uint32_t v = slots_[s].load(std::memory_order_relaxed);
        if (v == kMissing || vertices_[v].key == key) return v;
    }
}

}  // namespace vdbmesh::detail
