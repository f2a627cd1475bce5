#pragma once
// Private: a uniform hash grid over the bounding boxes of a changing set of triangles, for the
// local intersection checks of decimate_mesh().

#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace vdbmesh::detail {

class TriangleHash {
public:
    using Box = std::array<std::array<float, 3>, 2>;  ///< lo, hi

    /// Cells are cubes of @a cell_size world units.
    explicit TriangleHash(double cell_size) : inverse_(1.0 / cell_size) {}

    void insert(std::uint32_t triangle, const Box& box) { for_cells(box, [&](std::uint64_t key) { cells_[key].push_back(triangle); }); }

    /// @a box must be the box the triangle was inserted with.
    void erase(std::uint32_t triangle, const Box& box) {
        for_cells(box, [&](std::uint64_t key) {
            std::vector<std::uint32_t>& cell = cells_[key];
            for (std::size_t i = 0; i < cell.size(); ++i) {
                if (cell[i] == triangle) {
                    cell[i] = cell.back();
                    cell.pop_back();
                    break;
                }
            }
        });
    }

    /// Calls visit(triangle) for the triangles sharing a cell with @a box (a triangle may be
    /// visited more than once).
    template <class Visit>
    void visit(const Box& box, Visit&& visit) const {
        for_cells(box, [&](std::uint64_t key) {
            const auto cell = cells_.find(key);
            if (cell == cells_.end()) return;
            for (const std::uint32_t triangle : cell->second) visit(triangle);
        });
    }

private:
    template <class Call>
    void for_cells(const Box& box, Call&& call) const {
        std::array<std::int64_t, 3> lo{}, hi{};
        for (int k = 0; k < 3; ++k) lo[k] = cell_of(box[0][k]), hi[k] = cell_of(box[1][k]);
        for (std::int64_t x = lo[0]; x <= hi[0]; ++x) {
            for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
                for (std::int64_t z = lo[2]; z <= hi[2]; ++z) call(key(x, y, z));
            }
        }
    }
    std::int64_t cell_of(float coordinate) const { return std::int64_t(std::floor(double(coordinate) * inverse_)); }
    static std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) {
        constexpr std::uint64_t kMask = (std::uint64_t{1} << 21) - 1;  // 21 bits per axis
        return (std::uint64_t(x) & kMask) | (std::uint64_t(y) & kMask) << 21 | (std::uint64_t(z) & kMask) << 42;
    }

    double inverse_;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

}  // namespace vdbmesh::detail
