// The octree of one block for intersection-free contouring: unit cells merge into cells of 2,
// 4 and 8 voxels, bottom-up, when
//  - every child is a leaf (a unit cell, or a cell merged before),
//  - each of the 12 edges of the merged cell changes sign at most once along its samples, and
//    on each of its 6 faces the surface traces at most one open chain (no loop, no ambiguous
//    unit face): so one crossing per minimal edge and one segment per minimal face stand for
//    it (Ju, Losasso, Schaefer and Warren 2002 test the same at the cell's corners),
//  - the Marching Cubes surface inside is one disk (connected, Euler characteristic 1, no
//    ambiguous unit face): its boundary is the single cycle on the cell's faces, which the
//    fan round the cell's vertex reproduces,
//  - the QEF vertex lies within the error of the tangent plane of every surface sample in
//    the cell (so the fan stays near the surface).

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include "mesh/ifc_block.h"
#include "mesh/ifc_fan.h"
#include "mesh/ifc_qef.h"
#include "mesh/mc_table.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh::detail {

unsigned IfcSamples::config(int x, int y, int z) const {
    unsigned config = 0;
    for (unsigned c = 0; c < 8; ++c) config |= unsigned(in(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2))) << c;
    return config;
}

void load_ifc_samples(openvdb::FloatGrid::ConstAccessor& accessor, const SampleClassifier& classifier, IfcSamples& samples) {
    for (int x = -1; x < kIfcSampleDim - 1; ++x) {
        for (int y = -1; y < kIfcSampleDim - 1; ++y) {
            for (int z = -1; z < kIfcSampleDim - 1; ++z) {
                const openvdb::Coord ijk = samples.origin.offsetBy(x, y, z);
                const int i = IfcSamples::index(x, y, z);
                samples.value[i] = classifier.sample_value(ijk, accessor.getValue(ijk));
                samples.inside[i] = classifier.inside(samples.value[i]);
            }
        }
    }
}

namespace {

/// Central-difference gradient at local sample (x, y, z), one-sided at the samples' ring;
/// zero where a difference is not finite (beyond the scan box).
Point3d gradient(const IfcSamples& s, int x, int y, int z) {
    Point3d g;
    const std::array<int, 3> p = {x, y, z};
    for (int a = 0; a < 3; ++a) {
        std::array<int, 3> lo = p, hi = p;
        lo[a] = std::max(p[a] - 1, -1);
        hi[a] = std::min(p[a] + 1, kIfcSampleDim - 2);
        const double d = (s.at(hi[0], hi[1], hi[2]) - s.at(lo[0], lo[1], lo[2])) / double(hi[a] - lo[a]);
        g[a] = std::isfinite(d) ? d : 0.0;
    }
    return g;
}

}  // namespace

Hermite edge_hermite(const IfcSamples& s, double iso, int x, int y, int z, int axis) {
    const int x1 = x + (axis == 0), y1 = y + (axis == 1), z1 = z + (axis == 2);
    const Point3d p0 = {double(s.origin.x() + x), double(s.origin.y() + y), double(s.origin.z() + z)};
    Point3d p1 = p0;
    p1[axis] += 1.0;
    Hermite h;
    h.point = edge_crossing(p0, s.at(x, y, z), p1, s.at(x1, y1, z1), iso);
    const double t = h.point[axis] - p0[axis];
    const Point3d g0 = gradient(s, x, y, z), g1 = gradient(s, x1, y1, z1);
    double length = 0;
    for (int a = 0; a < 3; ++a) {
        h.normal[a] = (1 - t) * g0[a] + t * g1[a];
        length += h.normal[a] * h.normal[a];
    }
    length = std::sqrt(length);
    if (!(length > 0) || !std::isfinite(length)) {
        // Beyond the scan box, or a flat spot: the surface is taken across the edge.
        h.normal = {0, 0, 0};
        h.normal[axis] = 1;
    } else {
        for (double& n : h.normal) n /= length;
    }
    return h;
}

namespace {

/// Number of connected components of each Marching Cubes case (triangles sharing a cell edge).
const std::array<std::uint8_t, 256>& mc_component_counts() {
    static const std::array<std::uint8_t, 256> counts = [] {
        std::array<std::uint8_t, 256> result{};
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
            result[config] = std::uint8_t(components);
        }
        return result;
    }();
    return counts;
}

/// Joins, in the union-find @a parent, the crossed ones among a unit face's four edges (node
/// ids), as the surface's segment across the face does; returns how many are crossed (4: an
/// ambiguous face, left unjoined).
template <typename Crossed, typename Parent>
int join_face_crossings(const std::array<int, 4>& edges, const Crossed& crossed, Parent& parent) {
    auto find = [&](int i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    int first = -1, count = 0;
    for (int e : edges) {
        if (!crossed[e]) continue;
        ++count;
        if (first < 0) first = e;
        else if (count == 2) parent[find(e)] = find(first);
    }
    return count;
}

/// The surface's trace on a square of unit faces.
struct FaceTrace {
    int boundary_crossings = 0;  ///< crossed grid edges on the square's perimeter
    int components = 0;          ///< connected pieces (chains and loops)
    bool ambiguous = false;      ///< some unit face has all 4 edges crossed
    /// One open chain or nothing, no loop, no ambiguous face.
    bool at_most_one_chain() const { return !ambiguous && boundary_crossings <= 2 && components * 2 == boundary_crossings; }
};

/// The trace on the square of @a size unit faces at local sample @a origin, normal to @a axis.
FaceTrace trace_square(const IfcSamples& s, const std::array<int, 3>& origin, int axis, int size) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    const int u_edges = size * (size + 1);
    std::array<int, 2 * kIfcBlock * (kIfcBlock + 1)> parent;
    std::array<bool, 2 * kIfcBlock * (kIfcBlock + 1)> crossed{};
    auto point = [&](int i, int j) {
        std::array<int, 3> p = origin;
        p[u] += i;
        p[w] += j;
        return p;
    };
    // Node ids: u-edges (i, j) -> i * (size + 1) + j, w-edges (i, j) -> u_edges + i * size + j.
    FaceTrace trace;
    for (int i = 0; i < size; ++i) {
        for (int j = 0; j <= size; ++j) {
            const auto p = point(i, j);
            const int id = i * (size + 1) + j;
            crossed[id] = s.crossed(p[0], p[1], p[2], u);
            parent[id] = id;
            if (crossed[id] && (j == 0 || j == size)) ++trace.boundary_crossings;
        }
    }
    for (int i = 0; i <= size; ++i) {
        for (int j = 0; j < size; ++j) {
            const auto p = point(i, j);
            const int id = u_edges + i * size + j;
            crossed[id] = s.crossed(p[0], p[1], p[2], w);
            parent[id] = id;
            if (crossed[id] && (i == 0 || i == size)) ++trace.boundary_crossings;
        }
    }
    auto find = [&](int i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    for (int i = 0; i < size; ++i) {
        for (int j = 0; j < size; ++j) {
            const std::array<int, 4> edges = {i * (size + 1) + j, i * (size + 1) + j + 1, u_edges + i * size + j,
                                              u_edges + (i + 1) * size + j};
            if (join_face_crossings(edges, crossed, parent) == 4) {
                trace.ambiguous = true;
                return trace;
            }
        }
    }
    for (int id = 0; id < 2 * u_edges; ++id) trace.components += crossed[id] && find(id) == id;
    return trace;
}

/// Sign changes along the samples of the grid line from local sample @a start, @a size steps along @a axis.
int sign_changes(const IfcSamples& s, std::array<int, 3> p, int axis, int size) {
    int changes = 0;
    for (int k = 0; k < size; ++k, ++p[axis]) changes += s.crossed(p[0], p[1], p[2], axis);
    return changes;
}

enum class CellState : std::uint8_t {
    inner,  ///< not a leaf: a child could not be merged, or this merge was refused
    empty,  ///< a leaf holding no surface
    surface,  ///< a leaf holding surface: a unit cell, or a merged cell holding one disk
};

class BlockOctree {
public:
    /// The octree of the block of @a samples into @a out.
    void build(const IfcSamples& samples, double iso, double error, IfcBlockCells& out) {
        s_ = &samples;
        iso_ = iso;
        error_ = error;
        collect_hermite();
        init_unit_cells();
        for (int level = 1; level <= kIfcMaxLevel; ++level) merge_level(level);
        assign(out);
    }

private:
    static constexpr int kEdgeDim = kIfcBlock + 1;
    static int edge_index(int x, int y, int z, int axis) { return ((x * kEdgeDim + y) * kEdgeDim + z) * 3 + axis; }
    static int cells_per_axis(int level) { return kIfcBlock >> level; }
    static int cell_index(int level, int i, int j, int k) {
        const int n = cells_per_axis(level);
        return (i * n + j) * n + k;
    }

    /// Hermite data of the crossed edges of the block's cells (samples 0..8).
    void collect_hermite() {
        for (int x = 0; x <= kIfcBlock; ++x) {
            for (int y = 0; y <= kIfcBlock; ++y) {
                for (int z = 0; z <= kIfcBlock; ++z) {
                    for (int axis = 0; axis < 3; ++axis) {
                        const std::array<int, 3> p = {x, y, z};
                        const int i = edge_index(x, y, z, axis);
                        crossed_[i] = p[axis] < kIfcBlock && s_->crossed(x, y, z, axis);
                        if (crossed_[i]) hermite_[i] = edge_hermite(*s_, iso_, x, y, z, axis);
                    }
                }
            }
        }
    }

    /// Calls @a visit(hermite) for every crossed edge of the cell at local @a min of @a size.
    template <typename Visit>
    void for_each_crossing(const std::array<int, 3>& min, int size, Visit&& visit) const {
        for (int x = min[0]; x <= min[0] + size; ++x) {
            for (int y = min[1]; y <= min[1] + size; ++y) {
                for (int z = min[2]; z <= min[2] + size; ++z) {
                    const std::array<int, 3> p = {x, y, z};
                    for (int axis = 0; axis < 3; ++axis) {
                        if (p[axis] == min[axis] + size) continue;
                        const int i = edge_index(x, y, z, axis);
                        if (crossed_[i]) visit(hermite_[i]);
                    }
                }
            }
        }
    }

    void init_unit_cells() {
        for (int level = 0; level <= kIfcMaxLevel; ++level) {
            const int n = cells_per_axis(level);
            state_[level].assign(std::size_t(n * n * n), CellState::inner);
            qef_[level].assign(std::size_t(n * n * n), Qef3());
        }
        for (int x = 0; x < kIfcBlock; ++x) {
            for (int y = 0; y < kIfcBlock; ++y) {
                for (int z = 0; z < kIfcBlock; ++z) {
                    const unsigned config = s_->config(x, y, z);
                    const int i = cell_index(0, x, y, z);
                    Qef3& qef = qef_[0][i];
                    for_each_crossing({x, y, z}, 1, [&](const Hermite& h) { qef.add_plane(h.point, h.normal); });
                    if (config == 0 || config == 255) state_[0][i] = CellState::empty;
                    else state_[0][i] = CellState::surface;
                }
            }
        }
    }

    void merge_level(int level) {
        const int n = cells_per_axis(level);
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j) {
                for (int k = 0; k < n; ++k) merge_cell(level, i, j, k);
            }
        }
    }

    void merge_cell(int level, int i, int j, int k) {
        std::array<CellState, 8> child;
        bool any_surface = false;
        for (int c = 0; c < 8; ++c) {
            child[c] = state_[level - 1][cell_index(level - 1, 2 * i + (c & 1), 2 * j + ((c >> 1) & 1), 2 * k + (c >> 2))];
            if (child[c] == CellState::inner) return;  // stays inner
            any_surface |= child[c] == CellState::surface;
        }
        const int index = cell_index(level, i, j, k);
        if (!any_surface) {
            state_[level][index] = CellState::empty;
            return;
        }
        const int size = 1 << level;
        const std::array<int, 3> min = {i * size, j * size, k * size};
        Qef3 qef;
        for (int c = 0; c < 8; ++c) {
            qef.add(qef_[level - 1][cell_index(level - 1, 2 * i + (c & 1), 2 * j + ((c >> 1) & 1), 2 * k + (c >> 2))]);
        }
        // Cheapest and most often failing first.
        const Point3d vertex = solve_in_cell(qef, min, size);
        if (!within_error(vertex, min, size) || !fan_near_surface(vertex, min, size) ||
            !edges_and_faces_simple(min, size) || !surface_is_one_disk(min, size) || !surface_near_fan(vertex, min, size)) {
            return;
        }
        state_[level][index] = CellState::surface;
        qef_[level][index] = qef;
        vertex_[level][index] = vertex;
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

    bool edges_and_faces_simple(const std::array<int, 3>& min, int size) const {
        bool simple = true;
        for_each_cell_edge(min, size, [&](const std::array<int, 3>& p, int axis) { simple &= sign_changes(*s_, p, axis, size) <= 1; });
        if (!simple) return false;
        for (int axis = 0; axis < 3; ++axis) {
            for (int side = 0; side < 2; ++side) {
                std::array<int, 3> origin = min;
                origin[axis] += side * size;
                if (!trace_square(*s_, origin, axis, size).at_most_one_chain()) return false;
            }
        }
        return true;
    }

    /// Whether the Marching Cubes surface in the closed cell is one disk: no ambiguous unit
    /// face, connected, and Euler characteristic 1. Per unit cell, a component of n vertices
    /// is n - 2 triangles with n - 3 inner edges, so the characteristic is
    /// crossed edges - segments on unit faces + the cells' component counts.
    bool surface_is_one_disk(const std::array<int, 3>& min, int size) const {
        const int n = size + 1;
        auto node = [&](int dx, int dy, int dz, int axis) { return ((dx * n + dy) * n + dz) * 3 + axis; };
        std::array<int, kEdgeDim * kEdgeDim * kEdgeDim * 3> parent;  // entries below n^3 * 3 set below
        std::array<bool, kEdgeDim * kEdgeDim * kEdgeDim * 3> crossed;
        int vertices = 0;
        for (int dx = 0; dx < n; ++dx) {
            for (int dy = 0; dy < n; ++dy) {
                for (int dz = 0; dz < n; ++dz) {
                    const std::array<int, 3> d = {dx, dy, dz};
                    for (int axis = 0; axis < 3; ++axis) {
                        const int id = node(dx, dy, dz, axis);
                        parent[id] = id;
                        crossed[id] = d[axis] < size && s_->crossed(min[0] + dx, min[1] + dy, min[2] + dz, axis);
                        vertices += crossed[id];
                    }
                }
            }
        }
        auto find = [&](int i) {
            while (parent[i] != i) i = parent[i] = parent[parent[i]];
            return i;
        };
        int segments = 0;
        for (int normal = 0; normal < 3; ++normal) {
            const int u = (normal + 1) % 3, w = (normal + 2) % 3;
            for (int plane = 0; plane < n; ++plane) {
                for (int i = 0; i < size; ++i) {
                    for (int j = 0; j < size; ++j) {
                        std::array<int, 3> d{};
                        d[normal] = plane;
                        d[u] = i;
                        d[w] = j;
                        std::array<int, 3> du = d, dw = d;
                        ++du[u];
                        ++dw[w];
                        const std::array<int, 4> edges = {node(d[0], d[1], d[2], u), node(dw[0], dw[1], dw[2], u),
                                                          node(d[0], d[1], d[2], w), node(du[0], du[1], du[2], w)};
                        const int count = join_face_crossings(edges, crossed, parent);
                        if (count == 4) return false;
                        segments += count / 2;
                    }
                }
            }
        }
        int components = 0;
        for (int id = 0; id < n * n * n * 3; ++id) components += crossed[id] && find(id) == id;
        if (components != 1) return false;
        const auto& cell_components = mc_component_counts();
        int pieces = 0;
        for (int x = min[0]; x < min[0] + size; ++x) {
            for (int y = min[1]; y < min[1] + size; ++y) {
                for (int z = min[2]; z < min[2] + size; ++z) pieces += cell_components[s_->config(x, y, z)];
            }
        }
        return vertices - segments + pieces == 1;
    }

    Point3d solve_in_cell(const Qef3& qef, const std::array<int, 3>& min, int size) const {
        Point3d lo, hi;
        for (int a = 0; a < 3; ++a) {
            lo[a] = s_->origin[a] + min[a] + kIfcInteriorMargin;
            hi[a] = s_->origin[a] + min[a] + size - kIfcInteriorMargin;
        }
        return qef.solve(lo, hi);
    }

    bool within_error(const Point3d& v, const std::array<int, 3>& min, int size) const {
        bool ok = true;
        for_each_crossing(min, size, [&](const Hermite& h) {
            const double d = h.normal[0] * (v[0] - h.point[0]) + h.normal[1] * (v[1] - h.point[1]) + h.normal[2] * (v[2] - h.point[2]);
            ok &= std::abs(d) <= error_;
        });
        return ok;
    }

    /// Whether the vertex, and the midpoints of its spokes to the crossings of the cell's 12
    /// edges (the fan's triangles run along them), lie within the error of the isosurface, by
    /// the first-order estimate |f - iso| / |grad f| of the trilinear interpolant. The tangent
    /// planes alone let a vertex sit off a curved or thin surface.
    bool fan_near_surface(const Point3d& v, const std::array<int, 3>& min, int size) const {
        if (surface_distance(v) > error_) return false;
        bool near = true;
        for_each_cell_edge(min, size, [&](std::array<int, 3> p, int axis) {
            for (int k = 0; k < size && near; ++k, ++p[axis]) {
                const int i = edge_index(p[0], p[1], p[2], axis);
                if (!crossed_[i]) continue;
                Point3d mid;
                for (int a = 0; a < 3; ++a) mid[a] = 0.5 * (v[a] + hermite_[i].point[a]);
                near = surface_distance(mid) <= error_;
            }
        });
        return near;
    }

    /// Whether every crossing of the cell's grid edges (the Marching Cubes surface's vertices)
    /// lies within twice the error of the fan the cell will be.
    bool surface_near_fan(const Point3d& v, const std::array<int, 3>& min, int size) const {
        IfcFan fan(v);
        for (int axis = 0; axis < 3; ++axis) {
            for (int side = 0; side < 2; ++side) {
                std::array<Point3d, 2> ends;
                if (face_chord(min, size, axis, side, ends) == 2) fan.add_chord(ends[0], ends[1]);
            }
        }
        bool near = true;
        for_each_crossing(min, size, [&](const Hermite& h) { near = near && fan.near(h.point, 2 * error_); });
        return near;
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
                for (int k = 0; k < size; ++k, ++p[along]) {
                    const int i = edge_index(p[0], p[1], p[2], along);
                    if (!crossed_[i]) continue;
                    if (count < 2) ends[count] = hermite_[i].point;
                    ++count;
                }
            }
        }
        return count;
    }

    /// First-order distance (voxels) from global index point @a x in the block to the
    /// isosurface of the trilinear interpolant; 0 where a sample is beyond the scan box.
    double surface_distance(const Point3d& x) const {
        std::array<int, 3> cell;
        std::array<double, 3> t;
        for (int a = 0; a < 3; ++a) {
            const double local = x[a] - s_->origin[a];
            cell[a] = std::clamp(int(std::floor(local)), 0, kIfcBlock - 1);
            t[a] = local - cell[a];
        }
        std::array<double, 8> values;
        for (int c = 0; c < 8; ++c) values[c] = s_->at(cell[0] + (c & 1), cell[1] + ((c >> 1) & 1), cell[2] + (c >> 2));
        return trilinear_surface_distance(values, t, iso_);
    }

    /// Top down: the largest leaves become the block's cells.
    void assign(IfcBlockCells& out) {
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
                        std::uint16_t id = IfcBlockCells::kNoCell;
                        if (state == CellState::surface) {
                            id = std::uint16_t(out.cells.size());
                            out.cells.push_back({std::uint8_t(level), s_->origin.offsetBy(i * size, j * size, k * size),
                                                 vertex_[level][cell_index(level, i, j, k)]});
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
        out.root_leaf = state_[kIfcMaxLevel][0] != CellState::inner;
        out.root_qef = qef_[kIfcMaxLevel][0];
    }

    const IfcSamples* s_ = nullptr;
    double iso_ = 0;
    double error_ = 0;
    std::array<bool, kEdgeDim * kEdgeDim * kEdgeDim * 3> crossed_{};
    std::array<Hermite, kEdgeDim * kEdgeDim * kEdgeDim * 3> hermite_;
    std::array<std::vector<CellState>, kIfcMaxLevel + 1> state_;
    std::array<std::vector<Qef3>, kIfcMaxLevel + 1> qef_;
    std::array<std::array<Point3d, 64>, kIfcMaxLevel + 1> vertex_{};
};

}  // namespace

void build_ifc_cells(const IfcSamples& samples, double iso, double error, IfcBlockCells& cells) {
    // About 120 KB of Hermite data and the per-level arrays: once per thread, on the heap
    // (not a worker's stack), reused from block to block.
    thread_local const std::unique_ptr<BlockOctree> octree = std::make_unique<BlockOctree>();
    octree->build(samples, iso, error, cells);
}

}  // namespace vdbmesh::detail
