// The octree of one block for intersection-free contouring, top down: the block, else each of
// its cells of 4 voxels, else each of their cells of 2, stays whole (one vertex) when
//  - each of the 12 edges of the cell changes sign at most once along its samples, and on
//    each of its 6 faces the surface traces at most one open chain (no loop, no ambiguous
//    unit face): so one crossing per minimal edge and one segment per minimal face stand for
//    it (Ju, Losasso, Schaefer and Warren 2002 test the same at the cell's corners),
//  - the Marching Cubes surface inside is one disk (connected, Euler characteristic 1, no
//    ambiguous unit face): its boundary is the single cycle on the cell's faces, which the
//    fan round the cell's vertex reproduces,
//  - the QEF vertex lies within the error of the tangent plane of every surface sample in
//    the cell, and the fan and the surface lie within the error of each other.
// Every test looks at the whole cell, not at its children, so a cell may stay whole where a
// child alone could not (its fan need not match the child's part of the surface): top down
// is as safe as bottom up, finds the larger cells, and tests a smooth block once.

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>

#include "mesh/dc_block.h"
#include "mesh/dc_fan.h"
#include "mesh/dc_qef.h"
#include "mesh/dc_topology.h"
#include "mesh/mc_table.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh::detail {

namespace {

/// Per Marching Cubes case: whether the cell may be a leaf child in the 27-sign topology test
/// (dc_topology.h): no surface, or one component (a disk; triangles joined by shared cell
/// edges) and no ambiguous face (one chain per face).
const std::array<bool, 256>& simple_unit_cells() {
    static const std::array<bool, 256> simple = [] {
        std::array<bool, 256> result{};
        for (unsigned config = 0; config < 256; ++config) {
            const McCase& c = mc_case(config);
            std::array<int, 12> edge_owner;
            edge_owner.fill(-1);
            std::array<int, 6> parent;
            std::iota(parent.begin(), parent.end(), 0);
            auto find = [&](int i) {
                while (parent[i] != i) i = parent[i];
                return i;
            };
            for (int t = 0; t < c.triangle_count; ++t) {
                for (int k = 0; k < 3; ++k) {
                    int& owner = edge_owner[c.triangles[t][k]];
                    if (owner < 0) owner = t;
                    else parent[find(t)] = find(owner);
                }
            }
            int components = 0;
            for (int t = 0; t < c.triangle_count; ++t) components += find(t) == t;
            bool ambiguous = false;
            for (int axis = 0; axis < 3; ++axis) {
                const int u = (axis + 1) % 3, w = (axis + 2) % 3;
                for (int side = 0; side < 2; ++side) {
                    auto in = [&](int du, int dw) { return (config >> (side << axis | du << u | dw << w)) & 1; };
                    ambiguous |= in(0, 0) == in(1, 1) && in(1, 0) == in(0, 1) && in(0, 0) != in(1, 0);
                }
            }
            result[config] = components == 0 || (components == 1 && !ambiguous);
        }
        return result;
    }();
    return simple;
}

enum class CellState : std::uint8_t {
    inner,  ///< not a leaf: a child could not be merged, or this merge was refused
    empty,  ///< a leaf holding no surface
    surface,  ///< a leaf holding surface: a unit cell, or a merged cell holding one disk
};

class BlockOctree {
public:
    /// The octree of the block of @a samples into @a out.
    void build(const IfcSamples& samples, double iso, double error, bool sharp, IfcBlockCells& out) {
        s_ = &samples;
        iso_ = iso;
        error_ = error;
        sharp_ = sharp;
        out.sampled = true;
        out.inside_rows = samples.inside_rows;
        collect_hermite(out.crossings);
        init_unit_cells();
        sum_levels();
        refine(kIfcMaxLevel, 0, 0, 0);
        if (sharp_) place_unit_feature_vertices();
        assign(out);
        keep_parts(out);
        // Every block keeps these until the contour: at their sizes, not with push_back's slack
        // (up to as much again; about 14 MB of the bunny's peak at --error 0.25, above
        // volumeToMesh's at 0.25).
        out.crossings.shrink_to_fit();
        out.cells.shrink_to_fit();
    }

private:
    static constexpr int kEdgeDim = kIfcBlock + 1;
    static int edge_index(int x, int y, int z, int axis) { return ((x * kEdgeDim + y) * kEdgeDim + z) * 3 + axis; }
    /// edge_index() of the next edge along each axis, less this one's.
    static constexpr int kEdgeStride[3] = {kEdgeDim * kEdgeDim * 3, kEdgeDim * 3, 3};
    static int cells_per_axis(int level) { return kIfcBlock >> level; }
    /// A block's cells are named by a byte, kNoCell excluded.
    static constexpr int kMaxBlockCells = IfcBlockCells::kNoCell;
    /// `--sharp`: how far (voxels) the window's feature point may lie beyond a unit cell that
    /// takes it (clamped into the cell).
    static constexpr double kUnitFeatureReach = 1.0;
    static int cell_index(int level, int i, int j, int k) {
        const int n = cells_per_axis(level);
        return (i * n + j) * n + k;
    }

    /// Hermite data of the crossed edges of the block's cells (samples 0..8), and into
    /// @a contour_crossings where the mesh crosses the block's own ones (minimum sample in
    /// 0..7) along their axis, in the order (x, y, z, axis) the contour walks them, as
    /// edge_crossing() computes it with ifc_crossing_margin().
    void collect_hermite(std::vector<double>& contour_crossings) {
        crossings_.clear();
        hermite_.clear();
        slot_.fill(kNoSlot);
        contour_crossings.clear();
        const double margin = ifc_crossing_margin(error_);
        for (int x = 0; x <= kIfcBlock; ++x) {
            for (int y = 0; y <= kIfcBlock; ++y) {
                row_start_[x * kEdgeDim + y] = std::uint16_t(crossings_.size());
                // Bit z + 1 of along[axis]: the edge from (x, y, z) along axis is crossed; edges
                // leaving the block's samples 0..8 are not the block's.
                std::array<unsigned, 3> along{};
                for (int axis = 0; axis < 3; ++axis) {
                    const int p[2] = {x, y};
                    if (axis < 2 && p[axis] == kIfcBlock) continue;
                    along[axis] = s_->crossed_row(x, y, axis) & (axis == 2 ? 0x1feu : 0x3feu);
                }
                for (unsigned any = along[0] | along[1] | along[2]; any != 0; any &= any - 1) {
                    const int z = __builtin_ctz(any) - 1;
                    for (int axis = 0; axis < 3; ++axis) {
                        if (!((along[axis] >> (z + 1)) & 1u)) continue;
                        const int i = edge_index(x, y, z, axis);
                        slot_[i] = std::uint16_t(hermite_.size());
                        hermite_.push_back(edge_hermite(*s_, iso_, x, y, z, axis));
                        crossings_.push_back({std::uint8_t(x), std::uint8_t(y), std::uint8_t(z), std::uint8_t(axis)});
                        if (x < kIfcBlock && y < kIfcBlock && z < kIfcBlock) {
                            const double f0 = s_->at(x, y, z), f1 = s_->at(x + (axis == 0), y + (axis == 1), z + (axis == 2));
                            const int start[3] = {x, y, z};
                            contour_crossings.push_back(double(s_->origin[axis] + start[axis]) + crossing_parameter(f0, f1, iso_, margin));
                        }
                    }
                }
            }
        }
        row_start_[kEdgeDim * kEdgeDim] = std::uint16_t(crossings_.size());
    }

    /// Whether @a test(hermite) holds for every crossed edge of the cell at local @a min of
    /// @a size; stops at the first that fails.
    template <typename Test>
    bool all_crossings(const std::array<int, 3>& min, int size, Test&& test) const {
        // The crossings are listed by row (x, y), so only the cell's rows are read; the order
        // is the list's whatever the cell.
        for (int x = min[0]; x <= min[0] + size; ++x) {
            for (int y = min[1]; y <= min[1] + size; ++y) {
                const int row = x * kEdgeDim + y;
                for (int k = row_start_[row]; k < row_start_[row + 1]; ++k) {
                    const auto& c = crossings_[std::size_t(k)];
                    const int axis = c[3];
                    if (c[2] > min[2] + size) break;  // a row's crossings go up in z
                    if (c[2] < min[2] || c[2] > min[2] + size - (axis == 2)) continue;
                    if ((axis == 0 && x == min[0] + size) || (axis == 1 && y == min[1] + size)) continue;
                    if (!test(hermite_[std::size_t(k)])) return false;
                }
            }
        }
        return true;
    }

    ChildCornerSigns corner_signs(const std::array<int, 3>& min, int size) const {
        const int half = size / 2;
        return child_corner_signs([&](int x, int y, int z) { return s_->in(min[0] + x * half, min[1] + y * half, min[2] + z * half); });
    }

    void init_unit_cells() {
        // Sized once per thread; sum_levels() writes every cell above level 0, and a unit
        // cell's QEF is cleared when it first gets a plane (clearing all 585 QEFs of every
        // block, 65 KB, cost more than the planes).
        for (int level = 0; level <= kIfcMaxLevel; ++level) {
            const int n = cells_per_axis(level);
            state_[level].resize(std::size_t(n * n * n));
            qef_[level].resize(std::size_t(n * n * n));
        }
        // A unit cell holds surface iff one of its edges is crossed; each crossing's plane
        // goes to the (up to 4) unit cells round its edge.
        // The plane's QEF is formed once and added to each cell (the same sums, bit for bit,
        // as adding the plane to each: every term starts from zero).
        std::fill(state_[0].begin(), state_[0].end(), CellState::empty);
        for (std::size_t k = 0; k < crossings_.size(); ++k) {
            const auto& c = crossings_[k];
            const int axis = c[3], u = (axis + 1) % 3, w = (axis + 2) % 3;
            const Hermite& h = hermite_[k];
            Qef3 plane;
            plane.add_plane(h.point, h.normal);
            for (int q = 0; q < 4; ++q) {
                std::array<int, 3> cell = {c[0], c[1], c[2]};
                cell[u] -= q & 1;
                cell[w] -= q >> 1;
                if (cell[u] < 0 || cell[u] >= kIfcBlock || cell[w] < 0 || cell[w] >= kIfcBlock) continue;
                const int i = cell_index(0, cell[0], cell[1], cell[2]);
                if (state_[0][i] != CellState::surface) {
                    qef_[0][i] = plane;
                    state_[0][i] = CellState::surface;
                } else {
                    qef_[0][i].add(plane);
                }
            }
        }
    }

    /// The QEFs, states and topology of the cells of 2, 4 and 8 voxels from their children's:
    /// a cell holds surface (for now; refine() decides) when a child does, and is simple (one
    /// disk, one crossing per edge, one chain per face) when its children are and their 27
    /// corner signs say so.
    void sum_levels() {
        const auto& simple_units = simple_unit_cells();
        for (int x = 0; x < kIfcBlock; ++x) {
            for (int y = 0; y < kIfcBlock; ++y) {
                const unsigned mixed = s_->mixed_cells_row(x, y);  // cells without surface are simple
                for (int z = 0; z < kIfcBlock; ++z) {
                    simple_[0][cell_index(0, x, y, z)] = !((mixed >> (z + 1)) & 1u) || simple_units[s_->config(x, y, z)];
                }
            }
        }
        for (int level = 1; level <= kIfcMaxLevel; ++level) {
            const int n = cells_per_axis(level);
            const int m = 2 * n;  // children per axis
            std::array<int, 8> child_offset;  // of child c from child 0, in its level's arrays
            for (int c = 0; c < 8; ++c) child_offset[c] = ((c & 1) * m + ((c >> 1) & 1)) * m + (c >> 2);
            for (int i = 0; i < n; ++i) {
                for (int j = 0; j < n; ++j) {
                    for (int k = 0; k < n; ++k) {
                        const int index = cell_index(level, i, j, k);
                        const int first_child = cell_index(level - 1, 2 * i, 2 * j, 2 * k);
                        std::array<bool, 8> surface;
                        bool children_simple = true;
                        Qef3 sum;  // of the children holding surface: the others' QEFs are not kept
                        for (int c = 0; c < 8; ++c) {
                            const int child = first_child + child_offset[c];
                            surface[c] = state_[level - 1][child] == CellState::surface;
                            if (surface[c]) sum.add(qef_[level - 1][child]);
                            children_simple &= simple_[level - 1][child];
                        }
                        qef_[level][index] = sum;
                        const bool any_surface = std::any_of(surface.begin(), surface.end(), [](bool b) { return b; });
                        state_[level][index] = any_surface ? CellState::surface : CellState::empty;
                        const int size = 1 << level;
                        simple_[level][index] =
                            children_simple && (!any_surface || union_is_one_disk(corner_signs({i * size, j * size, k * size}, size), surface));
                    }
                }
            }
        }
    }

    /// Top down: the cell stays whole when it holds no surface or passes the merge tests,
    /// else its children are refined.
    void refine(int level, int i, int j, int k) {
        if (level == 0) return;
        const int index = cell_index(level, i, j, k);
        if (state_[level][index] == CellState::empty) return;
        if (can_merge(level, i, j, k)) return;
        state_[level][index] = CellState::inner;
        for (int c = 0; c < 8; ++c) refine(level - 1, 2 * i + (c & 1), 2 * j + ((c >> 1) & 1), 2 * k + (c >> 2));
    }

    bool can_merge(int level, int i, int j, int k) {
        const int size = 1 << level;
        const std::array<int, 3> min = {i * size, j * size, k * size};
        const int index = cell_index(level, i, j, k);
        // Cheapest and most often failing first.
        if (!simple_[level][index]) return false;
        const openvdb::Coord origin = s_->origin.offsetBy(min[0], min[1], min[2]);
        const Qef3& qef = qef_[level][index];
        feature_[level][index] = sharp_ && is_sharp_feature(qef) && place_feature_vertex(origin, min, size, qef, vertex_[level][index]);
        if (feature_[level][index]) return true;
        return ifc_place_vertex(origin, size, s_->scan_box, qef.minimiser(), [&](const Point3d& vertex) {
            if (!accurate(vertex, min, size, 0.0)) return false;
            vertex_[level][index] = vertex;
            return true;
        });
    }

    /// Whether @a vertex passes the merge's accuracy tests, each at its tolerance plus @a slack.
    bool accurate(const Point3d& vertex, const std::array<int, 3>& min, int size, double slack) const {
        return within_error(vertex, min, size, slack) && fan_near_surface(vertex, min, size, slack) &&
               surface_near_fan(vertex, min, size, slack);
    }

    /// `--sharp`: the feature point of a feature cell into @a vertex if it passes the accuracy
    /// tests kSharpReach beyond the error, clamped into the cell kIfcInteriorMargin from its
    /// faces: first where the faces of a wider window meet (window_feature_point()), then the
    /// cell's own QEF minimiser.
    bool place_feature_vertex(const openvdb::Coord& origin, const std::array<int, 3>& min, int size, const Qef3& qef,
                              Point3d& vertex) const {
        std::array<IfcVertexBox, 3> boxes;
        ifc_vertex_boxes(origin, size, s_->scan_box, boxes);
        const Point3d estimate = qef.minimiser();
        const auto offer = [&](const Point3d& point) {
            const Point3d candidate = boxes.back().clamp(point);
            if (!accurate(candidate, min, size, kSharpReach)) return false;
            vertex = candidate;
            return true;
        };
        const std::optional<Point3d> from_window = window_feature_point(s_->source, iso_, origin, size, estimate);
        return (from_window && offer(*from_window)) || offer(estimate);
    }

    /// `--sharp`: each unit cell left a leaf (a cell of 2 voxels round it was refused) whose
    /// surface is one disk without an ambiguous face (simple: the construction contours it like
    /// any merged cell) takes the feature point of its cell of 2 voxels' window, from its own
    /// QEF's estimate, when that point lies within kUnitFeatureReach of the cell (clamped into
    /// it) and passes the accuracy tests kSharpReach beyond the error; the others stay Marching
    /// Cubes cells. Along a tilted edge the cells of 2 voxels fail the topology tests (an edge
    /// crossed twice, docs/dmc.md); their unit cells do not.
    void place_unit_feature_vertices() {
        unit_feature_.fill(false);
        int cells = 0;  // merged leaves so far: a block's cells are named by a byte
        for (int level = 1; level <= kIfcMaxLevel; ++level) {
            const int n = cells_per_axis(level);
            for (int index = 0; index < n * n * n; ++index) cells += leaf(level, index) && state_[level][index] == CellState::surface;
        }
        const int n = cells_per_axis(1);
        for (int parent = 0; parent < n * n * n && cells < kMaxBlockCells; ++parent) {
            if (state_[1][parent] != CellState::inner) continue;
            std::optional<std::vector<WindowFace>> faces;  // read once for the parent's unit cells
            const std::array<int, 3> parent_min = {2 * (parent / (n * n)), 2 * (parent / n % n), 2 * (parent % n)};
            for (int c = 0; c < 8 && cells < kMaxBlockCells; ++c) {
                const std::array<int, 3> min = {parent_min[0] + (c & 1), parent_min[1] + ((c >> 1) & 1), parent_min[2] + (c >> 2)};
                const int unit = cell_index(0, min[0], min[1], min[2]);
                if (state_[0][unit] != CellState::surface || !simple_[0][unit]) continue;
                if (!faces) faces = window_faces(s_->source, iso_, s_->origin.offsetBy(parent_min[0], parent_min[1], parent_min[2]), 2);
                if (faces->size() < 2) break;
                const std::optional<Point3d> point = feature_point(*faces, qef_[0][unit].minimiser());
                if (!point) continue;
                std::array<IfcVertexBox, 3> boxes;
                ifc_vertex_boxes(s_->origin.offsetBy(min[0], min[1], min[2]), 1, s_->scan_box, boxes);
                const Point3d candidate = boxes.back().clamp(*point);
                if (squared_distance(candidate, *point) > kUnitFeatureReach * kUnitFeatureReach) continue;
                if (!accurate(candidate, min, 1, kSharpReach)) continue;
                unit_feature_[std::size_t(unit)] = true;
                unit_vertex_[std::size_t(unit)] = candidate;
                ++cells;
            }
        }
    }

    /// Whether the cell at @a index of @a level is a leaf: no cell above it stayed whole.
    bool leaf(int level, int index) const {
        const int n = cells_per_axis(level);
        int i = index / (n * n), j = index / n % n, k = index % n;
        for (int up = level + 1; up <= kIfcMaxLevel; ++up) {
            i /= 2, j /= 2, k /= 2;
            if (state_[up][cell_index(up, i, j, k)] != CellState::inner) return false;
        }
        return state_[level][index] != CellState::inner;
    }

    /// Bit 2 * axis + side for each face of the whole block the surface only clips (ifc_chord_spans_face()).
    std::uint8_t root_clipped_faces() const {
        std::uint8_t clipped = 0;
        for (int axis = 0; axis < 3; ++axis) {
            for (int side = 0; side < 2; ++side) {
                std::array<Point3d, 2> ends;
                if (face_chord({0, 0, 0}, kIfcBlock, axis, side, ends) == 2 && !ifc_chord_spans_face(ends[0], ends[1], kIfcBlock)) {
                    clipped |= std::uint8_t(1u << (2 * axis + side));
                }
            }
        }
        return clipped;
    }

    /// Calls @a visit(start, axis) for the start (local sample) and axis of each of the 12
    /// edges of the cell at @a min of @a size.
    template <typename Visit>
    static void for_each_cell_edge(const std::array<int, 3>& min, int size, Visit&& visit) {
        for (int axis = 0; axis < 3; ++axis) {
            const int u = (axis + 1) % 3, w = (axis + 2) % 3;
            for (int corner = 0; corner < 4; ++corner) {
                std::array<int, 3> p = min;
                p[u] += (corner & 1) * size;
                p[w] += (corner >> 1) * size;
                visit(p, axis);
            }
        }
    }

    bool within_error(const Point3d& v, const std::array<int, 3>& min, int size, double slack) const {
        const double tolerance = error_ + slack;
        return all_crossings(min, size, [&](const Hermite& h) {
            const double d = h.normal[0] * (v[0] - h.point[0]) + h.normal[1] * (v[1] - h.point[1]) + h.normal[2] * (v[2] - h.point[2]);
            return std::abs(d) <= tolerance;
        });
    }

    /// The point @a share of the way from @a v to @a p.
    static Point3d along_spoke(const Point3d& v, const Point3d& p, double share) {
        return {v[0] + share * (p[0] - v[0]), v[1] + share * (p[1] - v[1]), v[2] + share * (p[2] - v[2])};
    }

    /// Whether the vertex, and the points a quarter and half way along its spokes to the
    /// crossings of the cell's 12 edges (the fan's triangles run along them), lie within the
    /// error of the isosurface, by the first-order estimate |f - iso| / |grad f| of the trilinear
    /// interpolant. The tangent planes alone let a vertex sit off a curved or thin surface. The
    /// quarter points catch a vertex whose spokes leave the surface steeply near it (CThead at
    /// --error 1, 1,000,000 samples: Hausdorff 1.48 -> 1.07 voxels, for 66 more triangles).
    bool fan_near_surface(const Point3d& v, const std::array<int, 3>& min, int size, double slack) const {
        const double tolerance = error_ + slack;
        if (surface_distance(v) > tolerance) return false;
        bool near = true;
        for_each_cell_edge(min, size, [&](std::array<int, 3> p, int axis) {
            const int first = edge_index(p[0], p[1], p[2], axis);
            for (int k = 0, i = first; k < size && near; ++k, i += kEdgeStride[axis]) {
                if (slot_[i] == kNoSlot) continue;
                const Point3d& crossing = hermite_[slot_[i]].point;
                near = surface_distance(along_spoke(v, crossing, 0.5)) <= tolerance;
                // The crossing lies on the surface, so a quarter point within the error of it
                // is near; the estimate is asked only of the others.
                if (near && 0.75 * 0.75 * squared_distance(v, crossing) > tolerance * tolerance) {
                    near = surface_distance(along_spoke(v, crossing, 0.25)) <= tolerance;
                }
            }
        });
        return near;
    }

    /// Whether every crossing of the cell's grid edges (the Marching Cubes surface's vertices)
    /// lies within twice the error of the fan the cell will be.
    bool surface_near_fan(const Point3d& v, const std::array<int, 3>& min, int size, double slack) const {
        IfcFan fan(v);
        for (int axis = 0; axis < 3; ++axis) {
            for (int side = 0; side < 2; ++side) {
                std::array<Point3d, 2> ends;
                if (face_chord(min, size, axis, side, ends) == 2) fan.add_chord(ends[0], ends[1]);
            }
        }
        // A crossing on one of the cell's 12 edges ends the chords of both faces round it (the
        // cell is simple: each face holds at most one chain), so it is a vertex of the fan; where
        // the contour replaces it by the polygon of the cells round its edge, that polygon must
        // pass within the error of it (dc_polygons.cpp).
        Point3d lo, hi;
        for (int a = 0; a < 3; ++a) {
            lo[a] = s_->origin[a] + min[a];
            hi[a] = lo[a] + size;
        }
        const auto on_cell_edge = [&](const Point3d& p) {
            int on_faces = 0;
            for (int a = 0; a < 3; ++a) on_faces += p[a] == lo[a] || p[a] == hi[a];
            return on_faces >= 2;
        };
        const double tolerance = 2 * error_ + slack;
        return all_crossings(min, size, [&](const Hermite& h) { return on_cell_edge(h.point) || fan.near(h.point, tolerance); });
    }

    /// The crossings on the perimeter of the cell's face normal to @a axis on @a side (0: low,
    /// 1: high), up to two into @a ends; returns how many there are.
    int face_chord(const std::array<int, 3>& min, int size, int axis, int side, std::array<Point3d, 2>& ends) const {
        const int u = (axis + 1) % 3, w = (axis + 2) % 3;
        int count = 0;
        for (int along : {u, w}) {
            const int across = along == u ? w : u;
            for (int edge_side = 0; edge_side < 2; ++edge_side) {
                std::array<int, 3> p = min;
                p[axis] += side * size;
                p[across] += edge_side * size;
                const int first = edge_index(p[0], p[1], p[2], along);
                for (int k = 0, i = first; k < size; ++k, i += kEdgeStride[along]) {
                    if (slot_[i] == kNoSlot) continue;
                    if (count < 2) ends[count] = hermite_[slot_[i]].point;
                    ++count;
                }
            }
        }
        return count;
    }

    /// First-order distance (voxels) from global index point @a x in the block to the
    /// isosurface of the trilinear interpolant; 0 where a sample is beyond the scan box.
    double surface_distance(const Point3d& x) const {
        Point3d local;
        std::array<int, 3> cell;
        for (int a = 0; a < 3; ++a) {
            local[a] = x[a] - s_->origin[a];
            cell[a] = std::clamp(int(std::floor(local[a])), 0, kIfcBlock - 1);
        }
        return cell_surface_distance(local, cell, [&](int i, int j, int k) { return s_->at(i, j, k); }, iso_);
    }

    /// Top down: the largest leaves become the block's cells.
    void assign(IfcBlockCells& out) const {
        assign_leaves(out);
        out.root_leaf = state_[kIfcMaxLevel][0] != CellState::inner;
        out.root_qef = qef_[kIfcMaxLevel][0];
    }

    /// The leaves into @a out.
    void assign_leaves(IfcLeaves& out) const {
        out.level.fill(0);
        out.cell.fill(IfcBlockCells::kNoCell);
        out.cells.clear();
        for (int level = kIfcMaxLevel; level >= 1; --level) {
            const int n = cells_per_axis(level), size = 1 << level;
            for (int i = 0; i < n; ++i) {
                for (int j = 0; j < n; ++j) {
                    for (int k = 0; k < n; ++k) {
                        const CellState state = state_[level][cell_index(level, i, j, k)];
                        if (state != CellState::empty && state != CellState::surface) continue;
                        if (out.level[IfcBlockCells::unit_index(i * size, j * size, k * size)] != 0) continue;  // inside a larger leaf
                        std::uint8_t id = IfcBlockCells::kNoCell;
                        if (state == CellState::surface) {
                            id = std::uint8_t(out.cells.size());
                            out.cells.push_back({std::uint8_t(level), s_->origin.offsetBy(i * size, j * size, k * size),
                                                 vertex_[level][cell_index(level, i, j, k)], feature_[level][cell_index(level, i, j, k)]});
                        }
                        for (int x = i * size; x < (i + 1) * size; ++x) {
                            for (int y = j * size; y < (j + 1) * size; ++y) {
                                for (int z = k * size; z < (k + 1) * size; ++z) {
                                    out.level[IfcBlockCells::unit_index(x, y, z)] = std::uint8_t(level);
                                    out.cell[IfcBlockCells::unit_index(x, y, z)] = id;
                                }
                            }
                        }
                    }
                }
            }
        }
        if (!sharp_) return;
        for (int x = 0; x < kIfcBlock; ++x) {
            for (int y = 0; y < kIfcBlock; ++y) {
                for (int z = 0; z < kIfcBlock; ++z) {
                    const int unit = cell_index(0, x, y, z);
                    if (!unit_feature_[std::size_t(unit)] || out.level[IfcBlockCells::unit_index(x, y, z)] != 0) continue;
                    out.cell[IfcBlockCells::unit_index(x, y, z)] = std::uint8_t(out.cells.size());
                    out.cells.push_back({0, s_->origin.offsetBy(x, y, z), unit_vertex_[std::size_t(unit)], true});
                }
            }
        }
    }

    /// Where the whole block is one cell whose surface only clips some of its faces: the cells
    /// it would have without that one, into @a out.parts (dual_contouring.cpp, split_clipped_blocks()).
    void keep_parts(IfcBlockCells& out) {
        if (state_[kIfcMaxLevel][0] != CellState::surface) return;
        const std::uint8_t clipped = root_clipped_faces();
        if (!clipped) return;
        state_[kIfcMaxLevel][0] = CellState::inner;
        for (int c = 0; c < 8; ++c) refine(kIfcMaxLevel - 1, c & 1, (c >> 1) & 1, c >> 2);
        if (sharp_) place_unit_feature_vertices();
        out.parts = std::make_unique<IfcBlockCells::Parts>();
        out.parts->clipped_faces = clipped;
        assign_leaves(*out.parts);
    }

    const IfcSamples* s_ = nullptr;
    double iso_ = 0;
    double error_ = 0;
    bool sharp_ = false;  ///< `--sharp`: feature cells offer their feature point first (can_merge())
    /// Per grid edge of the block (edge_index()): its crossing's index in hermite_ and
    /// crossings_, or kNoSlot. The Hermite data itself is kept packed, in scan order, so the
    /// tests walk a few KB rather than a sparse 105 KB table.
    static constexpr std::uint16_t kNoSlot = 0xffff;
    std::array<std::uint16_t, kEdgeDim * kEdgeDim * kEdgeDim * 3> slot_{};
    std::vector<Hermite> hermite_;
    std::vector<std::array<std::uint8_t, 4>> crossings_;
    /// Where row (x, y) of crossings_ starts (index x * kEdgeDim + y; the last entry is the end).
    std::array<std::uint16_t, kEdgeDim * kEdgeDim + 1> row_start_{};  ///< the crossed edges: x, y, z, axis
    std::array<std::vector<CellState>, kIfcMaxLevel + 1> state_;
    std::array<std::vector<Qef3>, kIfcMaxLevel + 1> qef_;
    std::array<std::array<bool, kIfcBlock * kIfcBlock * kIfcBlock>, kIfcMaxLevel + 1> simple_{};
    std::array<std::array<Point3d, 64>, kIfcMaxLevel + 1> vertex_{};
    std::array<std::array<bool, 64>, kIfcMaxLevel + 1> feature_{};  ///< whether vertex_ is a feature point
    /// `--sharp`: the unit cells that took a feature point (place_unit_feature_vertices()), and where.
    std::array<bool, kIfcBlock * kIfcBlock * kIfcBlock> unit_feature_{};
    std::array<Point3d, kIfcBlock * kIfcBlock * kIfcBlock> unit_vertex_{};
};

}  // namespace

void build_ifc_cells(const IfcSamples& samples, double iso, double error, bool sharp, IfcBlockCells& cells) {
    // About 120 KB of Hermite data and the per-level arrays: once per thread, on the heap
    // (not a worker's stack), reused from block to block.
    thread_local const std::unique_ptr<BlockOctree> octree = std::make_unique<BlockOctree>();
    octree->build(samples, iso, error, sharp, cells);
}

}  // namespace vdbmesh::detail
