#pragma once
// The exact crossing check of the hold-back, local (private to src/labels). Every vertex stays
// within a voxel or two of its corner, so the triangles sit in a uniform grid of cells about
// two voxels wide and a triangle need only be tested against those sharing a cell with it.
// The first check tests every pair; the hold-back then moves a few vertices back, and a later
// check tests only the triangles that moved, against the others through the grid of the first
// check and against each other through a small index of their own.

#include <cstdint>
#include <vector>

#include "vdbmesh/geometry.h"
#include "vdbmesh/mesh.h"

namespace vdbmesh::labels_detail {

class CrossingCheck {
public:
    /// @a cell: the grid's cell size in world units (it only sets the work: the check is exact
    /// at any size).
    explicit CrossingCheck(double cell) : cell_(cell) {}

    /// Flags (per triangle) the triangles that are degenerate or meet another triangle of
    /// @a mesh beyond the corners they share (detail::triangles_intersect(), corners
    /// identified by index), and those other triangles, among the pairs with a triangle of
    /// @a moved. The first call tests every triangle; a later one @a moved (ascending): every
    /// triangle with a corner moved since the call before, the triangles themselves unchanged.
    std::vector<std::uint8_t> crossing_triangles(const Mesh& mesh, const std::vector<std::uint32_t>& moved);

private:
    using CellCoordinates = std::array<std::int32_t, 3>;
    struct Found;
    void build_grid(const Mesh& mesh);
    void test_all(const Mesh& mesh, Found& found) const;
    void test_moved(const Mesh& mesh, const std::vector<std::uint32_t>& moved, Found& found);
    CellCoordinates coordinates(const std::array<float, 3>& p) const;
    std::size_t index(const CellCoordinates& c) const {
        return (std::size_t(c[2]) * std::size_t(dims_[1]) + std::size_t(c[1])) * std::size_t(dims_[0]) + std::size_t(c[0]);
    }
    template <class Visit>
    void for_each_cell(std::uint32_t t, Visit&& visit) const;
    void update(const Mesh& mesh, const std::vector<std::uint32_t>& triangles);

    double cell_;
    double inverse_cell_ = 1;
    std::array<double, 3> origin_{};
    CellCoordinates dims_{};
    std::vector<detail::Box> boxes_;            ///< per triangle: its box now
    std::vector<CellCoordinates> lo_, hi_;       ///< per triangle: the cells its box spans now
    std::vector<std::uint8_t> degenerate_;
    std::vector<std::uint32_t> start_, list_;    ///< per cell: the triangles reaching it at the first check
    std::vector<std::uint8_t> moved_;            ///< per triangle: moved since the first check (its cells in list_ stale)
    std::vector<std::uint32_t> moved_list_;      ///< the same, ascending
};

}  // namespace vdbmesh::labels_detail
