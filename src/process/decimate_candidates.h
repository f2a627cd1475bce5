#pragma once
// Private to the decimator (decimate_*.cpp): a round's candidate edges and their sort by cost.

#include <tbb/parallel_for.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "process/decimate_geometry.h"

namespace vdbmesh::detail::decimation {

/// An edge a round considers, at the corner opposite it where it runs from its lower vertex
/// (the one kept) to its higher one.
struct Candidate {
    double cost;
    std::uint32_t corner;
    bool operator<(const Candidate& o) const { return cost != o.cost ? cost < o.cost : corner < o.corner; }
};
/// Sorts @a candidates, given in order of their corners, by cost (so in Candidate's order): a
/// stable least-significant-digit radix sort on the bits of the costs (non-negative doubles,
/// whose bits order as they do), 11 at a time, each pass over fixed chunks in parallel (the same
/// for any thread count); a pass is skipped where all share the digit.
inline void sort_by_cost(std::vector<Candidate>& candidates, std::vector<Candidate>& buffer) {
    constexpr int kDigitBits = 11;
    constexpr std::size_t kBuckets = std::size_t(1) << kDigitBits, kChunks = 16;
    const std::size_t size = candidates.size(), chunk = (size + kChunks - 1) / kChunks;
    buffer.resize(size);
    std::vector<std::array<std::uint32_t, kBuckets>> counts(kChunks);
    const auto key = [](const Candidate& c) {
        std::uint64_t bits;
        std::memcpy(&bits, &c.cost, sizeof bits);
        return bits;
    };
    for (int shift = 0; shift < 64; shift += kDigitBits) {
        const auto digit = [&](const Candidate& c) { return std::size_t(key(c) >> shift) & (kBuckets - 1); };
        tbb::parallel_for(std::size_t(0), kChunks, [&](std::size_t k) {
            counts[k].fill(0);
            for (std::size_t i = k * chunk; i < std::min(size, (k + 1) * chunk); ++i) ++counts[k][digit(candidates[i])];
        });
        std::size_t offset = 0;
        bool one_digit = false;
        for (std::size_t b = 0; b < kBuckets; ++b) {
            std::size_t in_bucket = 0;
            for (std::size_t k = 0; k < kChunks; ++k) {
                const std::uint32_t n = counts[k][b];
                counts[k][b] = std::uint32_t(offset + in_bucket), in_bucket += n;
            }
            one_digit |= in_bucket == size;
            offset += in_bucket;
        }
        if (one_digit) continue;
        tbb::parallel_for(std::size_t(0), kChunks, [&](std::size_t k) {
            for (std::size_t i = k * chunk; i < std::min(size, (k + 1) * chunk); ++i) buffer[counts[k][digit(candidates[i])]++] = candidates[i];
        });
        candidates.swap(buffer);
    }
}

inline constexpr Candidate kAboveAll{std::numeric_limits<double>::infinity(), kNone};  ///< (as a pivot: keeps every candidate)


}  // namespace vdbmesh::detail::decimation
