#pragma once
// Private: the intersection-free octree contouring (dual_contouring.cpp) of one 8^3 block of cells. A
// cell is the cube between 8 samples, as in Marching Cubes. Unit cells stay Marching Cubes
// cells; cells of 2, 4 and 8 voxels are merged bottom-up where the surface inside is one
// disk the cell's single vertex can stand for (dc_octree.cpp), and are contoured dually, as
// are the unit cells that take a `--sharp` feature point (cells of level 0 with a vertex).

#include <openvdb/openvdb.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <cstdint>
#include <vector>

#include "mesh/edge_crossing.h"
#include "mesh/dc_feature_window.h"
#include "mesh/dc_qef.h"
#include "mesh/sample_classifier.h"

namespace vdbmesh::detail {

inline constexpr int kIfcBlock = 8;        ///< cells per block edge, as a leaf node
inline constexpr int kIfcMaxLevel = 3;     ///< merged cells within a block: up to 2^3 = 8 voxels
inline constexpr int kIfcCoarseMaxLevel = 7;  ///< across blocks: up to a lower internal node, 128 voxels
inline constexpr int kIfcSampleDim = kIfcBlock + 3;  ///< samples -1..9: cells 0..7 and gradients

/// The samples a block reads, local coordinates in [-1, 9]. Values are kept as the grid's
/// floats (half the bytes to write per block; the meshers compute in double from them, and
/// every value, the scan box's infinities included, converts exactly). Which samples are inside
/// is kept as one bit per sample in rows along z, so crossed edges and cell configurations
/// come from a few bit operations per row.
struct IfcSamples {
    openvdb::Coord origin;
    std::array<float, kIfcSampleDim * kIfcSampleDim * kIfcSampleDim> value;
    /// Per row (x, y): bit z + 1 set when sample (x, y, z) is inside.
    std::array<std::uint16_t, kIfcSampleDim * kIfcSampleDim> inside_rows;

    static int index(int x, int y, int z) { return ((x + 1) * kIfcSampleDim + (y + 1)) * kIfcSampleDim + (z + 1); }
    static int row_index(int x, int y) { return (x + 1) * kIfcSampleDim + (y + 1); }
    std::uint16_t row(int x, int y) const { return inside_rows[row_index(x, y)]; }
    bool in(int x, int y, int z) const { return (row(x, y) >> (z + 1)) & 1u; }
    double at(int x, int y, int z) const { return value[index(x, y, z)]; }
    /// Whether the grid edge from local sample (x, y, z) along @a axis is crossed.
    bool crossed(int x, int y, int z, int axis) const {
        return in(x, y, z) != in(x + (axis == 0), y + (axis == 1), z + (axis == 2));
    }
    /// Bit z + 1 set for each z whose edge from sample (x, y, z) along @a axis is crossed (its
    /// far end must lie in the window; along z, bit 10 is always clear).
    std::uint16_t crossed_row(int x, int y, int axis) const {
        const std::uint16_t near = row(x, y);
        const std::uint16_t far = axis == 2 ? std::uint16_t(near >> 1) : row(x + (axis == 0), y + (axis == 1));
        return std::uint16_t((near ^ far) & (axis == 2 ? 0x3ffu : 0x7ffu));
    }
    /// Bit z + 1 set for each z whose unit cell at (x, y, z) has corners on both sides.
    std::uint16_t mixed_cells_row(int x, int y) const {
        const unsigned r[4] = {row(x, y), row(x + 1, y), row(x, y + 1), row(x + 1, y + 1)};
        const unsigned all_in = r[0] & r[1] & r[2] & r[3], any_in = r[0] | r[1] | r[2] | r[3];
        return std::uint16_t(~(all_in & (all_in >> 1)) & (any_in | (any_in >> 1)) & 0x3ffu);
    }
    /// The scanned box (the classifier's), where the grid has one; samples beyond it take its
    /// outside value.
    const openvdb::CoordBBox* scan_box = nullptr;
    /// Where the samples were read from: `--sharp` reads a wider window round a feature cell.
    FeatureWindowSource source;
    /// Whether every sample is on the same side.
    bool uniform() const;
    /// Marching Cubes configuration of the unit cell at local (x, y, z): bit c for corner c inside.
    unsigned config(int x, int y, int z) const;
};

void load_ifc_samples(openvdb::FloatGrid::ConstAccessor& accessor, const SampleClassifier& classifier, IfcSamples& samples);

/// The crossing of the crossed edge from local sample (x, y, z) along @a axis (index space,
/// global) and the surface normal there (unit length, from central differences).
struct Hermite {
    Point3d point;
    Point3d normal;
};
Hermite edge_hermite(const IfcSamples& samples, double iso, int x, int y, int z, int axis);

/// A merged cell holding surface: its level (size 2^level), minimum corner and vertex (index
/// space). A cell larger than a block is copied into each block it covers. Level 0: a unit cell
/// that took a `--sharp` feature point, contoured like a merged cell.
struct IfcCell {
    std::uint8_t level;
    openvdb::Coord min;
    Point3d vertex;  ///< strictly inside the cell
    /// Whether the vertex is a `--sharp` feature point (is_sharp_feature()), held to the error
    /// plus kSharpReach (its polygons too, dc_polygons.cpp).
    bool feature = false;
};

/// The leaves of a block's octree: per unit cell its leaf's level and merged cell, and the
/// merged cells holding surface.
struct IfcLeaves {
    using UnitArray = std::array<std::uint8_t, kIfcBlock * kIfcBlock * kIfcBlock>;
    /// Per unit cell (local x * 64 + y * 8 + z): the level of the cell holding it (0: a unit
    /// cell, Marching Cubes unless it took a `--sharp` feature point).
    UnitArray level{};
    /// Per unit cell: index into @a cells of its merged cell, or kNoCell (a Marching Cubes unit
    /// cell, or merged without surface).
    UnitArray cell;  // at most 1 + 8 + 64 merged cells, and unit feature cells up to 255 in all
    std::vector<IfcCell> cells;
};

/// The cells of one block.
struct IfcBlockCells : IfcLeaves {
    /// Whether the whole block is one leaf (one merged cell, or no surface), and the QEF of
    /// its surface: what merging across blocks starts from. A block never built holds no surface.
    bool root_leaf = true;
    Qef3 root_qef;
    /// Where the whole block is one cell whose surface only clips some of its faces
    /// (ifc_chord_spans_face() fails there; bit 2 * axis + side of clipped_faces): the block's
    /// leaves without that one, which split_clipped_blocks() (dual_contouring.cpp) may put in its place.
    struct Parts : IfcLeaves {
        std::uint8_t clipped_faces = 0;
    };
    std::unique_ptr<Parts> parts;
    /// What the contour reads of the block's samples, kept from the octree's pass so that they
    /// are not loaded twice (build_ifc_cells()): whether there are any
    /// (a block the coarse merge added holds no surface of its own), the window's rows of
    /// inside bits, and the crossings of the block's own crossed edges along their axis, in
    /// the contour's order.
    bool sampled = false;
    std::array<std::uint16_t, kIfcSampleDim * kIfcSampleDim> inside_rows{};
    std::vector<double> crossings;
    /// Whether split_clipped_blocks() (dual_contouring.cpp) has decided this block, and whether it split
    /// it: a split block was one 8-voxel cell, which is what its neighbours' decisions read, so
    /// blocks may be decided in any order (the bricked driver decides them layer by layer).
    bool split_decided = false;
    bool was_split = false;

    static constexpr std::uint8_t kNoCell = 0xff;
    /// All unit cells, no surface: a block never built.
    IfcBlockCells() { cell.fill(kNoCell); }
    static int unit_index(int x, int y, int z) { return (x * kIfcBlock + y) * kIfcBlock + z; }
};

/// The blocks' cells, found by the origin of their block.
struct IfcCellGrid {
    std::vector<openvdb::Coord> origins;  ///< sorted
    /// In the same order; null for a block never built (no surface). Each is allocated by the
    /// task that builds it, so the memory is first touched in parallel, not in one serial resize.
    std::vector<std::unique_ptr<IfcBlockCells>> blocks;
    /// The indices of the 27 blocks round block @a b (at neighbour_slot(); itself at 13), -1
    /// where there is none.
    std::array<std::ptrdiff_t, 27> neighbours(std::size_t b) const;
    /// Where neighbours() puts the block @a dx, @a dy, @a dz blocks (each -1, 0 or 1) away.
    static constexpr std::size_t neighbour_slot(int dx, int dy, int dz) { return std::size_t((dx + 1) * 9 + (dy + 1) * 3 + dz + 1); }
    /// The cells of block @a b (all unit cells without surface if it was never built).
    const IfcBlockCells& block(std::size_t b) const;
    /// The cells of block @a b, allocated empty if it was never built.
    IfcBlockCells& block_for_writing(std::size_t b);
};

/// How far a merged cell's vertex stays inside its cell at least, and the segment between two
/// cells' vertices inside their shared face for the face test (voxels): far above the float
/// rounding of the output, so containment survives it.
inline constexpr double kIfcInteriorMargin = 1e-2;

/// A box a merged cell's vertex is kept in (index space, global).
struct IfcVertexBox {
    Point3d lo, hi;
    Point3d clamp(const Point3d& p) const {
        return {std::clamp(p[0], lo[0], hi[0]), std::clamp(p[1], lo[1], hi[1]), std::clamp(p[2], lo[2], hi[2])};
    }
};

/// The boxes a merged cell's vertex is kept in, in the order tried: the first whose vertex
/// passes the merge's accuracy tests is kept. A vertex near a face of its cell makes slivers
/// with the triangles over that face, so first 0.15 then 0.1 of the cell's size from its faces,
/// at most half a voxel (a vertex must still reach a face of the scan box, half a voxel beyond
/// the last samples), then kIfcInteriorMargin. A wider margin trades the surface's normals for
/// angles (compare at --error 1, angles under 10 degrees and mean normal deviation, with 0.1 and
/// 0.01 / with 0.15, 0.1 and 0.01: engine 0.79%, 6.6 degrees / 0.63%, 7.3; CThead 0.67%, 10.0 /
/// 0.42%, 10.9; walnut 0.72%, 13.7 / 0.34%, 14.8; 0.2 first gave fewer small angles at 1 but
/// more at 0.5, 0.15 then 0.01 more everywhere). Only kIfcInteriorMargin on a side where the
/// cell's own samples go beyond @a scan_box: the distance estimates read no distance there, so
/// they could not tell a vertex pulled off the surface. (Sessions 9-10 narrowed every side of a
/// cell whose tests' samples, one beyond the cell for gradients, went beyond the box; the
/// CThead point that rule was made for, 1.7 voxels from the mesh, was a thin wall's tip that a
/// polygon dropped, which polygon_near() in dc_polygons.cpp now keeps.)
inline void ifc_vertex_boxes(const openvdb::Coord& min, int size, const openvdb::CoordBBox* scan_box,
                             std::array<IfcVertexBox, 3>& boxes) {
    const std::array<double, 3> margins = {std::min(0.15 * size, 0.5), std::min(0.1 * size, 0.5), kIfcInteriorMargin};
    for (int a = 0; a < 3; ++a) {
        const bool low_beyond = scan_box && min[a] < scan_box->min()[a];
        const bool high_beyond = scan_box && min[a] + size > scan_box->max()[a];
        for (int t = 0; t < 3; ++t) {
            boxes[t].lo[a] = min[a] + (low_beyond ? kIfcInteriorMargin : margins[t]);
            boxes[t].hi[a] = min[a] + size - (high_beyond ? kIfcInteriorMargin : margins[t]);
        }
    }
}

/// Offers @a accept(vertex) the QEF's @a minimiser clamped into each of ifc_vertex_boxes() in
/// turn, skipping a box that leaves the vertex where the last offer had it (a minimiser inside
/// the widest box is offered once), until @a accept returns true; returns whether it did.
template <class Accept>
bool ifc_place_vertex(const openvdb::Coord& min, int size, const openvdb::CoordBBox* scan_box, const Point3d& minimiser,
                      Accept&& accept) {
    std::array<IfcVertexBox, 3> boxes;
    ifc_vertex_boxes(min, size, scan_box, boxes);
    Point3d offered = {NAN, NAN, NAN};
    for (const IfcVertexBox& box : boxes) {
        const Point3d vertex = box.clamp(minimiser);
        if (vertex == offered) continue;
        offered = vertex;
        if (accept(vertex)) return true;
    }
    return false;
}

/// How far (a share of the edge) the mesh's crossings are kept from their edge's samples at
/// @a error: a vertex moves at most that far along its edge, which keeps Marching Cubes' slivers
/// from the ends of the edges (README, "fewer slivers than Marching Cubes").
inline double ifc_crossing_margin(double error) { return std::min(error, 0.25); }

/// Builds the cells of one block: merges where the QEF vertex stays within @a error (voxels)
/// of every surface sample in the cell and the topology tests pass. Keeps too what the
/// contour reads of the samples (IfcBlockCells::sampled, inside_rows, crossings), on the
/// same walk over the crossed edges. With @a sharp (`--sharp`), a cell holding a sharp edge or
/// corner (is_sharp_feature()) first offers its QEF minimiser, clamped into the cell, to the
/// same tests at the error plus kSharpReach, and keeps today's vertex when they refuse it.
void build_ifc_cells(const IfcSamples& samples, double iso, double error, bool sharp, IfcBlockCells& cells);

/// Merges on across blocks, bottom-up under each lower internal node (cells of 16 to 128
/// voxels, in parallel per node), where every child is a leaf, the surface inside is one
/// disk and the cell's fan stays within the error; the merged cells replace the blocks' own.
void merge_ifc_coarse_cells(const openvdb::FloatGrid& grid, const SampleClassifier& classifier, double error, IfcCellGrid& cells);

}  // namespace vdbmesh::detail
