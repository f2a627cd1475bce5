// StreamWeld: see stream_weld.h.
#include "analysis/stream_weld.h"

#include <cstring>
#include <limits>
#include <string>

#include "vdbmesh/error.h"

namespace vdbmesh::detail {

void StreamWeld::add(const std::array<std::array<float, 3>, 3>& corners) {
    for (const auto& corner : corners) {
        CornerKey key{};
        std::memcpy(key.data(), corner.data(), 3 * sizeof(float));  // the bits, as read_stl() compares them
        key[3] = std::uint32_t(corners_ >> 32), key[4] = std::uint32_t(corners_);
        by_position_.add(key);
        ++corners_;
    }
}

std::uint64_t StreamWeld::number_vertices() {
    std::uint64_t vertices = 0;
    CornerKey previous{};
    by_position_.merge([&](const CornerKey& key) {
        const bool same = vertices > 0 && std::memcmp(key.data(), previous.data(), 3 * sizeof(std::uint32_t)) == 0;
        if (!same) {
            if (vertices == std::numeric_limits<std::uint32_t>::max()) {
                throw Error("STL mesh: more than 2^32 - 1 distinct corner positions (vertex numbers are 32 bits)");
            }
            ++vertices;
        }
        by_corner_.add({key[3], key[4], std::uint32_t(vertices - 1)});
        previous = key;
    });
    return vertices;
}

}  // namespace vdbmesh::detail
