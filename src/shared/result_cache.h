#pragma once
// Private: result matching (Parker and Udeshi, section 3): the result of an operation on a node
// and the neighbours it reads, stored under their ids so that every repetition of the same
// neighbourhood is a lookup. Thread-safe; a result depends on its key only, so which thread
// computes it first (two may, harmlessly) never changes what is returned.

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <shared_mutex>
#include <unordered_map>

namespace vdbmesh::detail {

template <std::size_t N>
struct IdKeyHash {
    std::size_t operator()(const std::array<std::uint32_t, N>& key) const {
        std::uint64_t h = 0x9e3779b97f4a7c15ull;
        for (std::uint32_t id : key) {
            h ^= id + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
            h *= 0xff51afd7ed558ccdull;
        }
        return std::size_t(h ^ (h >> 33));
    }
};

/// Key equality written out: std::array's == is a memcmp call, which stood out in profiles of
/// the lookups.
template <std::size_t N>
struct IdKeyEqual {
    bool operator()(const std::array<std::uint32_t, N>& a, const std::array<std::uint32_t, N>& b) const {
        std::uint32_t differ = 0;
        for (std::size_t i = 0; i < N; ++i) differ |= a[i] ^ b[i];
        return differ == 0;
    }
};

/// A cache of values of type V under keys of N node ids.
template <std::size_t N, class V>
class ResultCache {
public:
    using Key = std::array<std::uint32_t, N>;

    /// The value under @a key, computed by compute() (which may use other caches) when missing.
    /// The reference stays valid as long as the cache.
    template <class F>
    const V& get(const Key& key, F&& compute) {
        Shard& shard = shards_[IdKeyHash<N>()(key) % kShards];
        lookups_.fetch_add(1, std::memory_order_relaxed);
        {
            std::shared_lock lock(shard.mutex);
            const auto it = shard.map.find(key);
            if (it != shard.map.end()) return *it->second;
        }
        auto value = std::make_unique<V>(compute());
        misses_.fetch_add(1, std::memory_order_relaxed);
        std::unique_lock lock(shard.mutex);
        const auto [it, inserted] = shard.map.emplace(key, std::move(value));
        return *it->second;
    }

    std::uint64_t lookups() const { return lookups_.load(); }
    std::uint64_t misses() const { return misses_.load(); }
    std::size_t size() const {
        std::size_t n = 0;
        for (const Shard& s : shards_) n += s.map.size();
        return n;
    }

private:
    static constexpr std::size_t kShards = 64;
    struct Shard {
        std::shared_mutex mutex;
        std::unordered_map<Key, std::unique_ptr<V>, IdKeyHash<N>, IdKeyEqual<N>> map;
    };
    std::array<Shard, kShards> shards_;
    std::atomic<std::uint64_t> lookups_{0}, misses_{0};
};

}  // namespace vdbmesh::detail
