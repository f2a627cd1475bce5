#pragma once
// Private: the cells of the dual surface (dual_surface.cpp): per 8^3 block of cells, each
// cell's corner configuration and its vertices (one per edge group, dual_surface_groups.h),
// with the lookups the quads and the proof need.

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <vector>

#include "mesh/sample_classifier.h"
#include "mesh/surface_blocks.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh::detail {

inline constexpr int kDualBlockCells = kBlockDim * kBlockDim * kBlockDim;

/// A vertex is kept this far (in voxels) inside its cell's faces: the triangles round a grid
/// edge then lie strictly inside the 2x2x1 block of cells round it, far above the float
/// rounding of the written coordinates (the proof's locality, dual_surface_proof.h).
inline constexpr double kDualInteriorMargin = 1e-3;

/// The cells of one block whose minimum corners lie in it.
struct DualBlock {
    openvdb::Coord origin;
    std::array<std::uint8_t, kDualBlockCells> config{};  ///< bit c: corner c inside (0, 255: no surface)
    /// The configuration whose edge groups the cell takes: config, or its complement where its
    /// only ambiguous face is joined on both sides (dual_surface_cells.cpp, grouping()).
    std::array<std::uint8_t, kDualBlockCells> grouping{};
    std::array<std::uint16_t, kDualBlockCells> first_vertex{};  ///< the cell's first vertex, in the block
    /// The crossed grid edges the block owns (minimum voxel in it): cell index * 3 + axis.
    std::vector<std::uint16_t> crossed_edges;
    std::vector<Point3> projected;  ///< per vertex (index space): on the trilinear isosurface
    std::vector<Point3> mean;       ///< per vertex (index space): its crossings' mean
    std::vector<std::uint16_t> vertex_cell;  ///< per vertex: its cell's index in the block
    std::size_t first = 0;          ///< the global index of its first vertex
    std::size_t first_quad = 0;     ///< the global index of the quad of its first crossed edge

    static int cell_index(int x, int y, int z) { return (x * kBlockDim + y) * kBlockDim + z; }
};

/// A quad round a crossed grid edge: its four vertices counter-clockwise seen from outside.
struct DualQuad {
    std::array<std::uint32_t, 4> vertex;

    /// Its two triangles, split along the diagonal 1-3 (@a split_13) or 0-2.
    std::array<std::array<std::uint32_t, 3>, 2> triangles(bool split_13) const {
        if (split_13) return {{{vertex[0], vertex[1], vertex[3]}, {vertex[1], vertex[2], vertex[3]}}};
        return {{{vertex[0], vertex[1], vertex[2]}, {vertex[0], vertex[2], vertex[3]}}};
    }
};

/// The vertices of one cell: global indices first .. first + count - 1.
struct DualCellVertices {
    std::uint32_t first = 0;
    std::uint32_t count = 0;
};

/// Every block holding a cell the surface crosses, with its cells' vertices, the quads (in the
/// blocks' order, a block's by its crossed edges) and each vertex's star (the quads holding it).
class DualCells {
public:
    /// The blocks of @a grid (surface_blocks()) with their cells' configurations and vertices,
    /// then the quads and stars, made in parallel.
    DualCells(const openvdb::FloatGrid& grid, const SampleClassifier& classifier);

    const std::vector<DualBlock>& blocks() const { return blocks_; }
    std::size_t vertex_count() const { return star_first_.size() - 1; }
    const std::vector<DualQuad>& quads() const { return quads_; }
    /// The quads holding vertex @a v (its star): star_quads()[star_first(v)] .. [star_first(v + 1) - 1].
    std::size_t star_first(std::uint32_t v) const { return star_first_[v]; }
    const std::vector<std::uint32_t>& star_quads() const { return star_; }
    /// The vertices of the cell whose minimum corner is @a cell (none where no surface).
    DualCellVertices cell_vertices(const openvdb::Coord& cell) const;
    /// Every cell's vertices, in the blocks' order.
    std::vector<DualCellVertices> every_cell() const;

    /// The block holding the cell whose minimum corner is @a cell, or null when none is stored.
    const DualBlock* block_of(const openvdb::Coord& cell) const;
    /// The minimum corner of the cell holding global vertex @a v.
    openvdb::Coord cell_of_vertex(std::uint32_t v) const;

private:
    void make_vertices(const openvdb::FloatGrid& grid, const SampleClassifier& classifier);
    void make_quads();
    /// The global index of the vertex of cell @a cell's group holding cell edge @a edge
    /// (crossed; @a block holds the cell), and the edge's @a rank in that group.
    std::uint32_t vertex(const DualBlock* block, const openvdb::Coord& cell, int edge, std::uint8_t& rank) const;
    /// The quad round the crossed grid edge from @a voxel along @a axis, with each corner's
    /// slot in its vertex's star; @a below[d]: the block at the voxel's block's origin minus
    /// kBlockDim along each axis of bit d.
    DualQuad quad(const openvdb::Coord& voxel, int axis, const std::array<const DualBlock*, 8>& below, std::array<std::uint8_t, 4>& ranks) const;

    std::vector<DualBlock> blocks_;  ///< sorted by origin
    std::vector<DualQuad> quads_;
    std::vector<std::size_t> star_first_ = {0};  ///< per vertex, and one past the last
    std::vector<std::uint32_t> star_;
};

}  // namespace vdbmesh::detail
