#include "mesh/dc_key_index.h"

#include "vdbmesh/huge_pages.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace vdbmesh::detail {

IfcKeyIndex::IfcKeyIndex(const std::vector<std::uint64_t>& keys) {
    // At most three quarters full: linear probing then finds a key in about 2.5 slots on
    // average, and the table (first touched here, page by page) is half the size a half-full
    // one needs; its pages' zeroing was most of the weld's time (perf, bunny k = 2).
    int bits = 1;
    while (3 * (std::size_t(1) << bits) < 4 * keys.size()) ++bits;
    const std::size_t slot_count = std::size_t(1) << bits;
    mask_ = slot_count - 1;
    shift_ = 64 - bits;
    slots_.reset(new Slot[slot_count]);
    advise_huge_pages(slots_.get(), slot_count * sizeof(Slot));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, slot_count), [&](const auto& range) {
        for (std::size_t s = range.begin(); s != range.end(); ++s) slots_[s].key.store(kEmpty, std::memory_order_relaxed);
    });
    // Which vertex lands in which slot depends on the threads' order; what find() returns
    // does not (keys are unique). A slot's index is written by the thread that claimed its key
    // and read only after the loop has ended.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keys.size()), [&](const auto& range) {
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            for (std::size_t s = first_slot(keys[v]);; s = (s + 1) & mask_) {
                std::uint64_t empty = kEmpty;
                if (slots_[s].key.compare_exchange_strong(empty, keys[v], std::memory_order_relaxed)) {
                    slots_[s].index = std::uint32_t(v);
                    break;
                }
            }
        }
    });
}

std::uint32_t IfcKeyIndex::find(std::uint64_t key) const {
    for (std::size_t s = first_slot(key);; s = (s + 1) & mask_) {
        const std::uint64_t held = slots_[s].key.load(std::memory_order_relaxed);
        if (held == key) return slots_[s].index;
        if (held == kEmpty) return kMissing;
    }
}

}  // namespace vdbmesh::detail
