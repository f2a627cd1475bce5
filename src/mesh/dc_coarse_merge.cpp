// Merging across blocks for intersection-free contouring: cells of 16 to 128 voxels, built
// bottom-up under each lower internal node of the tree, nodes in parallel.
//
// Every child of a candidate cell is a leaf merged whole before (a block's single cell, or a
// coarse cell), so the topology of the union follows from the children's 27 corner signs
// (dc_topology.h).
// Accuracy cannot be tested on every crossing in a cell of up to 128^3 voxels; it is tested,
// through the grid, on samples that scale with the cell:
//  - the RMS distance from the vertex to the tangent planes of the cell's crossings (the
//    summed QEF) is within the error;
//  - the fan (dc_fan.h), on a lattice of 8 steps per triangle side, lies within the error of
//    the trilinear isosurface (first-order estimate);
//  - the crossings of the grid lines a quarter of the cell apart lie within twice the error
//    of the fan, and the children's vertices (within the error of the surface) within it.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

#include "mesh/dc_block.h"
#include "mesh/dc_fan.h"
#include "mesh/dc_topology.h"

namespace vdbmesh::detail {

namespace {

using LowerNode = openvdb::FloatTree::RootNodeType::ChildNodeType::ChildNodeType;
constexpr int kNodeDim = int(LowerNode::DIM);
static_assert(kNodeDim == kIfcBlock << (kIfcCoarseMaxLevel - kIfcMaxLevel), "cells up to a lower internal node");
constexpr int kBlocksPerNode = kNodeDim / kIfcBlock;

/// Lattice steps per fan triangle side for the fan-to-surface test.
constexpr int kFanLatticeSteps = 8;
/// Grid lines a cell's size / kLineDivisions apart carry the crossings of the surface-to-fan test.
constexpr int kLineDivisions = 4;

enum class State : std::uint8_t { inner, empty, surface };

/// The traces of the surface on a cell's faces, each as the chord between its two ends.
struct FaceChords {
    std::array<std::array<Point3d, 2>, 6> ends;
    int count = 0;
};

struct Cell {
    State state = State::empty;
    Qef3 qef;
    Point3d vertex{};
};

class NodeMerger {
public:
    NodeMerger(openvdb::FloatGrid::ConstAccessor& accessor, const SampleClassifier& classifier, double error,
               IfcCellGrid& grid, const openvdb::Coord& origin)
        : accessor_(accessor), classifier_(classifier), iso_(classifier.iso()), error_(error), grid_(grid), origin_(origin) {}

    void run(const std::vector<std::size_t>& blocks) {
        init_blocks(blocks);
        for (int level = kIfcMaxLevel + 1; level <= kIfcCoarseMaxLevel; ++level) {
            const int n = per_axis(level);
            cells_[level].assign(std::size_t(n * n * n), Cell());
            for (int i = 0; i < n; ++i) {
                for (int j = 0; j < n; ++j) {
                    for (int k = 0; k < n; ++k) merge_cell(level, i, j, k);
                }
            }
        }
        assign();
    }

private:
    static int per_axis(int level) { return kNodeDim >> level; }
    static int index(int level, int i, int j, int k) { return (i * per_axis(level) + j) * per_axis(level) + k; }

    void init_blocks(const std::vector<std::size_t>& blocks) {
        block_index_.fill(-1);
        cells_[kIfcMaxLevel].assign(std::size_t(kBlocksPerNode * kBlocksPerNode * kBlocksPerNode), Cell());
        for (std::size_t b : blocks) {
            const openvdb::Coord local = grid_.origins[b] - origin_;
            const int i = index(kIfcMaxLevel, local.x() / kIfcBlock, local.y() / kIfcBlock, local.z() / kIfcBlock);
            block_index_[std::size_t(i)] = std::ptrdiff_t(b);
            const IfcBlockCells& block = grid_.block(b);
            Cell& cell = cells_[kIfcMaxLevel][std::size_t(i)];
            if (!block.root_leaf) cell.state = State::inner;
            else if (!block.cells.empty()) cell = {State::surface, block.root_qef, block.cells.front().vertex};
        }
    }

    void merge_cell(int level, int i, int j, int k) {
        std::array<bool, 8> surface{};
        std::array<const Cell*, 8> child;
        for (int c = 0; c < 8; ++c) {
            child[c] = &cells_[level - 1][std::size_t(index(level - 1, 2 * i + (c & 1), 2 * j + ((c >> 1) & 1), 2 * k + (c >> 2)))];
            if (child[c]->state == State::inner) {
                cells_[level][std::size_t(index(level, i, j, k))].state = State::inner;
                return;
            }
            surface[c] = child[c]->state == State::surface;
        }
        if (std::none_of(surface.begin(), surface.end(), [](bool b) { return b; })) return;  // empty
        const int size = 1 << level;
        const openvdb::Coord min = origin_.offsetBy(i * size, j * size, k * size);
        Cell& cell = cells_[level][std::size_t(index(level, i, j, k))];
        cell.state = State::inner;
        const ChildCornerSigns signs =
            child_corner_signs([&](int x, int y, int z) { return inside(min.offsetBy(x * size / 2, y * size / 2, z * size / 2)); });
        if (!union_is_one_disk(signs, surface)) return;
        const FaceChords chords = face_chords(min, size);
        Qef3 qef;
        for (int c = 0; c < 8; ++c) {
            if (surface[c]) qef.add(child[c]->qef);
        }
        const openvdb::CoordBBox* scan_box = classifier_.scan_box() ? &*classifier_.scan_box() : nullptr;
        ifc_place_vertex(min, size, scan_box, qef.minimiser(), [&](const Point3d& vertex) {
            if (!passes_accuracy_tests(qef, vertex, chords, child, surface, min, size)) return false;
            cell = {State::surface, qef, vertex};
            return true;
        });
    }

    /// Whether the cell's vertex and fan stand for its surface within the error: the QEF's RMS,
    /// the fan against the trilinear isosurface, the children's vertices and the grid lines'
    /// crossings against the fan (sampled, as merge_ifc_coarse_cells() says).
    bool passes_accuracy_tests(const Qef3& qef, const Point3d& vertex, const FaceChords& chords, const std::array<const Cell*, 8>& child,
                               const std::array<bool, 8>& surface, const openvdb::Coord& min, int size) {
        if (qef.residual(vertex) > qef.count() * error_ * error_) return false;
        IfcFan fan(vertex);
        for (int f = 0; f < chords.count; ++f) fan.add_chord(chords.ends[f][0], chords.ends[f][1]);
        if (!fan_near_surface(fan)) return false;
        for (int c = 0; c < 8; ++c) {
            if (surface[c] && !fan.near(child[c]->vertex, error_)) return false;
        }
        return lines_near_fan(fan, min, size);
    }

    double value(const openvdb::Coord& ijk) { return classifier_.sample_value(ijk, accessor_.getValue(ijk)); }
    bool inside(const openvdb::Coord& ijk) { return classifier_.inside(value(ijk)); }

    /// Calls @a visit(point) at each crossing of the grid line of @a steps unit edges from
    /// @a start along @a axis.
    template <typename Visit>
    bool for_each_line_crossing(openvdb::Coord start, int axis, int steps, Visit&& visit) {
        double f0 = value(start);
        for (int k = 0; k < steps; ++k) {
            openvdb::Coord next = start;
            next[axis] += 1;
            const double f1 = value(next);
            if (classifier_.inside(f0) != classifier_.inside(f1)) {
                const Point3d p0 = {double(start.x()), double(start.y()), double(start.z())};
                Point3d p1 = p0;
                p1[axis] += 1;
                if (!visit(edge_crossing(p0, f0, p1, f1, iso_))) return false;
            }
            start = next;
            f0 = f1;
        }
        return true;
    }

    /// The chords of the cell's faces the surface crosses: each one's two perimeter crossings.
    FaceChords face_chords(const openvdb::Coord& min, int size) {
        FaceChords chords;
        for (int axis = 0; axis < 3; ++axis) {
            const int u = (axis + 1) % 3, w = (axis + 2) % 3;
            for (int side = 0; side < 2; ++side) {
                std::array<Point3d, 2> ends;
                int count = 0;
                for (int along : {u, w}) {
                    const int across = along == u ? w : u;
                    for (int edge_side = 0; edge_side < 2; ++edge_side) {
                        openvdb::Coord start = min;
                        start[axis] += side * size;
                        start[across] += edge_side * size;
                        for_each_line_crossing(start, along, size, [&](const Point3d& p) {
                            if (count < 2) ends[count] = p;
                            ++count;
                            return true;
                        });
                    }
                }
                if (count == 2) chords.ends[chords.count++] = ends;
            }
        }
        return chords;
    }

    bool fan_near_surface(const IfcFan& fan) {
        return fan.sample(kFanLatticeSteps, [&](const Point3d& p) { return surface_distance(p) <= error_; });
    }

    bool lines_near_fan(IfcFan& fan, const openvdb::Coord& min, int size) {
        const int spacing = size / kLineDivisions;
        for (int axis = 0; axis < 3; ++axis) {
            for (int i = 0; i <= kLineDivisions; ++i) {
                for (int j = 0; j <= kLineDivisions; ++j) {
                    openvdb::Coord start = min;
                    start[(axis + 1) % 3] += i * spacing;
                    start[(axis + 2) % 3] += j * spacing;
                    if (!for_each_line_crossing(start, axis, size, [&](const Point3d& p) { return fan.near(p, 2 * error_); })) {
                        return false;
                    }
                }
            }
        }
        return true;
    }

    double surface_distance(const Point3d& x) {
        const std::array<int, 3> cell = {int(std::floor(x[0])), int(std::floor(x[1])), int(std::floor(x[2]))};
        return cell_surface_distance(x, cell, [&](int i, int j, int k) { return value(openvdb::Coord(i, j, k)); }, iso_);
    }

    /// Top down: each coarse leaf holding surface replaces the cells of the blocks it covers.
    void assign() {
        std::array<bool, kBlocksPerNode * kBlocksPerNode * kBlocksPerNode> covered{};
        for (int level = kIfcCoarseMaxLevel; level > kIfcMaxLevel; --level) {
            const int n = per_axis(level), blocks = 1 << (level - kIfcMaxLevel);
            for (int i = 0; i < n; ++i) {
                for (int j = 0; j < n; ++j) {
                    for (int k = 0; k < n; ++k) {
                        const Cell& cell = cells_[level][std::size_t(index(level, i, j, k))];
                        if (cell.state != State::surface || covered[std::size_t(index(kIfcMaxLevel, i * blocks, j * blocks, k * blocks))]) continue;
                        const int size = 1 << level;
                        const IfcCell merged{std::uint8_t(level), origin_.offsetBy(i * size, j * size, k * size), cell.vertex};
                        for (int x = i * blocks; x < (i + 1) * blocks; ++x) {
                            for (int y = j * blocks; y < (j + 1) * blocks; ++y) {
                                for (int z = k * blocks; z < (k + 1) * blocks; ++z) {
                                    const std::size_t b = std::size_t(index(kIfcMaxLevel, x, y, z));
                                    covered[b] = true;
                                    if (block_index_[b] >= 0) replace_cells(grid_.block_for_writing(std::size_t(block_index_[b])), merged);
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    static void replace_cells(IfcBlockCells& block, const IfcCell& merged) {
        block.level.fill(merged.level);
        block.cell.fill(0);
        block.cells.assign(1, merged);
    }

    openvdb::FloatGrid::ConstAccessor& accessor_;
    const SampleClassifier& classifier_;
    double iso_;
    double error_;
    IfcCellGrid& grid_;
    openvdb::Coord origin_;
    std::array<std::ptrdiff_t, kBlocksPerNode * kBlocksPerNode * kBlocksPerNode> block_index_;
    std::array<std::vector<Cell>, kIfcCoarseMaxLevel + 1> cells_;
};

}  // namespace

void merge_ifc_coarse_cells(const openvdb::FloatGrid& grid, const SampleClassifier& classifier, double error, IfcCellGrid& cells) {
    if (error <= 0) return;  // the dual error-0 mesh merges no cell
    // The blocks of each lower internal node, nodes in the order of their origins.
    std::vector<std::pair<openvdb::Coord, std::size_t>> by_node(cells.origins.size());
    for (std::size_t b = 0; b < cells.origins.size(); ++b) {
        const openvdb::Coord& o = cells.origins[b];
        by_node[b] = {openvdb::Coord(o.x() & ~(kNodeDim - 1), o.y() & ~(kNodeDim - 1), o.z() & ~(kNodeDim - 1)), b};
    }
    std::sort(by_node.begin(), by_node.end());
    std::vector<std::size_t> node_starts;
    for (std::size_t i = 0; i < by_node.size(); ++i) {
        if (i == 0 || by_node[i].first != by_node[i - 1].first) node_starts.push_back(i);
    }
    node_starts.push_back(by_node.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, node_starts.size() - 1), [&](const auto& range) {
        auto accessor = grid.getConstAccessor();
        std::vector<std::size_t> blocks;
        for (std::size_t n = range.begin(); n != range.end(); ++n) {
            blocks.clear();
            for (std::size_t i = node_starts[n]; i < node_starts[n + 1]; ++i) blocks.push_back(by_node[i].second);
            // About 0.6 MB of per-level cells: on the heap, not a worker's stack.
            auto merger = std::make_unique<NodeMerger>(accessor, classifier, error, cells, by_node[node_starts[n]].first);
            merger->run(blocks);
        }
    });
}

}  // namespace vdbmesh::detail
