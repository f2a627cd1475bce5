#pragma once
// Private: STL corners welded by exact position without holding them, for the bounded check
// (issue 28). read_stl() welds corners whose coordinates are bit-identical; here the corners
// are sorted by those bits (an external sort), which numbers the vertices in position order,
// then sorted back by corner, which gives each triangle its vertices in file order. The
// numbering differs from read_stl()'s (order of first appearance), which no count depends on.

#include <array>
#include <cstddef>
#include <cstdint>

#include "analysis/external_sort.h"

namespace vdbmesh::detail {

class StreamWeld {
public:
    /// Each sort gathers runs of @a run_records records.
    explicit StreamWeld(std::size_t run_records) : by_position_(run_records), by_corner_(run_records) {}
    void add(const std::array<std::array<float, 3>, 3>& corners);
    /// Numbers the distinct positions; returns how many there are.
    /// @throw Error for more than 2^32 - 1 of them (vertex numbers are 32 bits, as everywhere).
    std::uint64_t number_vertices();
    /// Calls @a visit(triangle) for each triangle in file order, with its vertex numbers.
    template <class Visit>
    void triangles(Visit&& visit) {
        std::array<std::uint32_t, 3> triangle{};
        std::uint64_t corner = 0;
        by_corner_.merge([&](const CornerVertex& record) {
            triangle[corner % 3] = record[2];
            if (++corner % 3 == 0) visit(triangle);
        });
    }
    std::size_t runs() const { return by_position_.runs() + by_corner_.runs(); }

private:
    using CornerKey = std::array<std::uint32_t, 5>;     ///< x, y, z bits, corner number (high, low word)
    using CornerVertex = std::array<std::uint32_t, 3>;  ///< corner number (high, low word), vertex
    ExternalSorter<CornerKey> by_position_;
    ExternalSorter<CornerVertex> by_corner_;
    std::uint64_t corners_ = 0;
};

}  // namespace vdbmesh::detail
