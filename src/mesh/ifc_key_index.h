#pragma once
// Private: finding a welded vertex by its key (ifc.cpp). The weld looks up three keys per
// triangle; a binary search over half a million vertices missed the cache about ten times per
// lookup and was half of the weld. Open addressing finds most keys at the first slot.

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "mesh/ifc_polygons.h"

namespace vdbmesh::detail {

class IfcKeyIndex {
public:
    /// Indexes @a vertices (unique keys), built in parallel. The slots hold vertex indices only
    /// (4 bytes each, at most half full) and compare keys through @a vertices, which must
    /// outlive the index: so it adds little to the weld's peak memory.
    explicit IfcKeyIndex(const std::vector<IfcVertex>& vertices);
    /// The index of the vertex with @a key, or kMissing.
    std::uint32_t find(std::uint64_t key) const;

    static constexpr std::uint32_t kMissing = 0xffffffffu;

private:
    std::size_t first_slot(std::uint64_t key) const;

    const std::vector<IfcVertex>& vertices_;
    std::size_t mask_ = 0;
    int shift_ = 63;
    std::unique_ptr<std::atomic<std::uint32_t>[]> slots_;
};

}  // namespace vdbmesh::detail
