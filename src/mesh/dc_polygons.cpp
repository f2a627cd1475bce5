// Polygons of intersection-free octree contouring, after Ju and Udeshi, "Intersection-free
// Contouring on an Octree Grid" (Pacific Graphics 2006), with Marching Cubes in unit cells.
//
// Why no two triangles cross. Every merged cell C is cut into pyramids from its vertex v_C
// (strictly inside C) over its minimal faces, and each pyramid over a face f shared with
// another merged cell into tetrahedra (v_C, x_f, e) over the minimal edges e of f, where x_f
// is a point strictly inside f (a `--sharp` unit cell with a feature point is a merged cell of
// size 1: one disk with no ambiguous face, as any merged cell). The other unit cells stay whole.
// Each triangle lies in one of these pieces, or in the union of the pieces around one edge, and
// pieces meet only on their boundaries, where the triangles share their edges:
//  - unit cells: Marching Cubes triangles, inside the cube;
//  - a merged cell C next to a unit cell across unit face f: the triangle (v_C, p_e, p_q) over
//    the surface's segment on f, inside the pyramid (v_C, f);
//  - a crossed minimal edge e with a merged cell on some side: the fan around its crossing
//    p_e: (p_e, v_i, v_i+1) when the segment v_i v_i+1 passes strictly inside their face
//    (the face test; x_f is that crossing, and the triangle lies in the tetrahedron
//    (e, v_i, v_i+1)), else the face's two triangles over the chord p_e q to the other
//    crossing q on the face's rim (a merged cell's face carries one open chain, so there is
//    exactly one): (p_e, v_i, q) and (p_e, q, v_i+1), inside the pyramids (v_i, f) and
//    (v_i+1, f), which then hold no other triangle;
//  - the same edge with only merged cells around it and every face test passed: the polygon
//    v_1..v_k without p_e, triangulated from one corner, when the flip of the tetrahedra
//    (e, v_i, v_i+1) into (e_0 | e_1, v_1, v_j, v_j+1) keeps every orientation (the edge
//    test): the new tetrahedra then tile the same region, and the triangles are their faces.
//    The polygon must also pass within the error of p_e (an accuracy test, not a safety one);
//    else the fan keeps p_e.
// The tests use a margin far above the float rounding of the output (kIfcInteriorMargin,
// kOrientationFloor), so what holds in double holds for the written floats.

#include "mesh/dc_polygons.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "mesh/mc_table.h"
#include "vdbmesh/error.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh::detail {

std::array<std::ptrdiff_t, 27> IfcCellGrid::neighbours(std::size_t b) const {
    // Origins are sorted by x, then y, then z: the three blocks of one column (fixed x and y)
    // are consecutive, so one search per column finds them (9 searches, not 26).
    std::array<std::ptrdiff_t, 27> found;
    const openvdb::Coord& centre = origins[b];
    for (int column = 0; column < 9; ++column) {
        const openvdb::Coord low = centre.offsetBy((column / 3 - 1) * kIfcBlock, (column % 3 - 1) * kIfcBlock, -kIfcBlock);
        auto it = column == 4 ? origins.begin() + std::ptrdiff_t(b) - (b > 0 && origins[b - 1] == low)
                              : std::lower_bound(origins.begin(), origins.end(), low);
        for (int dz = 0; dz < 3; ++dz) {
            const bool here = it != origins.end() && *it == low.offsetBy(0, 0, dz * kIfcBlock);
            found[neighbour_slot(column / 3 - 1, column % 3 - 1, dz - 1)] = here ? it - origins.begin() : -1;
            it += here;
        }
    }
    return found;
}

const IfcBlockCells& IfcCellGrid::block(std::size_t b) const {
    static const IfcBlockCells never_built;
    return blocks[b] ? *blocks[b] : never_built;
}

IfcBlockCells& IfcCellGrid::block_for_writing(std::size_t b) {
    if (!blocks[b]) blocks[b] = std::make_unique<IfcBlockCells>();
    return *blocks[b];
}

namespace {

/// Six times a tetrahedron's volume (voxels^3) below which a flip is not trusted.
constexpr double kOrientationFloor = 1e-3;

// ---- Vertex keys: kind (2 bits), payload (5 bits), x, y, z (19 bits each, biased) ----
constexpr int kCoordBits = 19;
constexpr int kKindShift = 62, kPayloadShift = 57;
constexpr std::int64_t kCoordBias = std::int64_t(1) << (kCoordBits - 1);

/// Throws unless every key a block at @a origin makes fits in kCoordBits per axis: keys name
/// grid points at most a lower internal node (a coarse cell's face) beyond the block.
void check_key_range(const openvdb::Coord& origin) {
    constexpr std::int64_t kReach = (kIfcBlock << (kIfcCoarseMaxLevel - kIfcMaxLevel)) + kIfcBlock;
    for (int a = 0; a < 3; ++a) {
        if (origin[a] - kReach + kCoordBias < 0 || origin[a] + kReach + kCoordBias >= (std::int64_t(1) << kCoordBits)) {
            throw Error("contouring: grid coordinates beyond +-2^18");
        }
    }
}

/// The key of a grid point of a block that passed check_key_range().
std::uint64_t make_key(unsigned kind, unsigned payload, const openvdb::Coord& p) {
    std::uint64_t key = (std::uint64_t(kind) << kKindShift) | (std::uint64_t(payload) << kPayloadShift);
    for (int a = 0; a < 3; ++a) key |= std::uint64_t(std::int64_t(p[a]) + kCoordBias) << (kCoordBits * (2 - a));
    return key;
}
std::uint64_t edge_key(const openvdb::Coord& min_sample, int axis) { return make_key(0, unsigned(axis), min_sample); }

/// What to add to a key to move its grid point by (dx, dy, dz) (a few voxels): the biased
/// fields take it without a carry into the next field, the block having passed
/// check_key_range().
constexpr std::uint64_t key_offset(int dx, int dy, int dz) {
    return std::uint64_t(std::int64_t(dx) * (std::int64_t(1) << (2 * kCoordBits)) + std::int64_t(dy) * (std::int64_t(1) << kCoordBits) + dz);
}

/// Per Marching Cubes edge (mc_case.h numbering): its key less the key of its cell's minimum
/// corner, as edge_key() of its first corner would give.
const std::array<std::uint64_t, 12>& mc_edge_key_offsets() {
    static const std::array<std::uint64_t, 12> offsets = [] {
        std::array<std::uint64_t, 12> result{};
        for (int e = 0; e < 12; ++e) {
            const unsigned c0 = kEdgeCorners[e][0], c1 = kEdgeCorners[e][1];
            const unsigned axis = (c0 ^ c1) == 1 ? 0 : (c0 ^ c1) == 2 ? 1 : 2;
            result[std::size_t(e)] = (std::uint64_t(axis) << kPayloadShift) + key_offset(int(c0 & 1), int((c0 >> 1) & 1), int(c0 >> 2));
        }
        return result;
    }();
    return offsets;
}

constexpr unsigned kCellKind = 1;

/// A leaf cell of the octree as seen from an edge: a unit Marching Cubes cell or a merged cell.
struct CellView {
    openvdb::Coord min;
    int size = 1;
    int level = 0;
    const Point3d* vertex = nullptr;  ///< merged cells
    bool feature = false;             ///< a `--sharp` feature point (IfcCell::feature)
    bool merged() const { return vertex != nullptr; }
    bool operator==(const CellView& o) const { return min == o.min && size == o.size; }
    std::uint64_t key() const { return make_key(kCellKind, unsigned(level), min); }
};

Point3d to_point(const openvdb::Coord& c) { return {double(c.x()), double(c.y()), double(c.z())}; }

double orient(const Point3d& a, const Point3d& b, const Point3d& c, const Point3d& d) {
    const double b0 = b[0] - a[0], b1 = b[1] - a[1], b2 = b[2] - a[2];
    const double c0 = c[0] - a[0], c1 = c[1] - a[1], c2 = c[2] - a[2];
    const double d0 = d[0] - a[0], d1 = d[1] - a[1], d2 = d[2] - a[2];
    return b0 * (c1 * d2 - c2 * d1) - b1 * (c0 * d2 - c2 * d0) + b2 * (c0 * d1 - c1 * d0);
}

/// The contour's walk over a block: per unit cell in order, @a mixed_cell(x, y, z) where its
/// corners differ, then @a crossed_edge(x, y, z, axis) for each of its three edges that is
/// crossed (the block's own edges); rows of bits skip the cells and edges without surface.
/// The crossed edges come in the order (x, y, z, axis) in which build_ifc_cells() records
/// their crossings (IfcBlockCells::crossings).
template <class MixedCell, class CrossedEdge>
void walk_block(const IfcSamples& s, MixedCell&& mixed_cell, CrossedEdge&& crossed_edge) {
    static constexpr unsigned kBlockBits = ((1u << kIfcBlock) - 1) << 1;  // z = 0..7 at bits 1..8
    for (int x = 0; x < kIfcBlock; ++x) {
        for (int y = 0; y < kIfcBlock; ++y) {
            const unsigned mixed = s.mixed_cells_row(x, y) & kBlockBits;
            const std::array<unsigned, 3> along = {s.crossed_row(x, y, 0) & kBlockBits, s.crossed_row(x, y, 1) & kBlockBits,
                                                   s.crossed_row(x, y, 2) & kBlockBits};
            for (unsigned any = mixed | along[0] | along[1] | along[2]; any != 0; any &= any - 1) {
                const int z = __builtin_ctz(any) - 1;
                if ((mixed >> (z + 1)) & 1u) mixed_cell(x, y, z);
                for (int axis = 0; axis < 3; ++axis) {
                    if ((along[axis] >> (z + 1)) & 1u) crossed_edge(x, y, z, axis);
                }
            }
        }
    }
}

class BlockContour {
public:
    /// @a s holds the block's origin and rows of inside bits (not its values).
    BlockContour(const IfcSamples& s, const SampleClassifier& classifier, openvdb::FloatGrid::ConstAccessor& accessor,
                 const IfcCellGrid& grid, std::size_t block, double error, const openvdb::math::Transform& transform, IfcBlockOutput& out)
        : s_(s), classifier_(classifier), accessor_(accessor), grid_(grid), block_(block), error_(error), transform_(transform), out_(out) {}

    void run() {
        check_key_range(s_.origin);
        origin_key_ = edge_key(s_.origin, 0);
        const std::array<std::ptrdiff_t, 27> around = grid_.neighbours(block_);
        for (int n = 0; n < 27; ++n) neighbour_[n] = around[n] < 0 ? nullptr : &grid_.block(std::size_t(around[n]));
        const IfcBlockCells& cells = grid_.block(block_);
        for (const IfcCell& cell : cells.cells) add_vertex(make_key(kCellKind, cell.level, cell.min), cell.vertex);
        crossings_ = &cells.crossings;
        next_crossing_ = 0;
        walk_block(
            s_,
            [&](int x, int y, int z) {
                const int u = IfcBlockCells::unit_index(x, y, z);
                if (cells.level[u] == 0 && cells.cell[u] == IfcBlockCells::kNoCell) marching_cube(x, y, z);
            },
            [&](int x, int y, int z, int axis) {
                crossed_edge(x, y, z, axis);
                ++next_crossing_;
            });
    }

private:
    void add_vertex(std::uint64_t key, const Point3d& index_point) {
        const openvdb::Vec3d w = transform_.indexToWorld(openvdb::Vec3d(index_point[0], index_point[1], index_point[2]));
        out_.vertices.push_back({key, {float(w[0]), float(w[1]), float(w[2])}});
    }
    void add_triangle(std::uint64_t a, std::uint64_t b, std::uint64_t c) { out_.triangles.push_back({a, b, c}); }

    void marching_cube(int x, int y, int z) {
        const McCase& c = mc_case(s_.config(x, y, z));
        const std::uint64_t cell_key = origin_key_ + key_offset(x, y, z);
        const auto& offsets = mc_edge_key_offsets();
        for (int t = 0; t < c.triangle_count; ++t) {
            const auto& edges = c.triangles[t];
            add_triangle(cell_key + offsets[std::size_t(edges[0])], cell_key + offsets[std::size_t(edges[1])], cell_key + offsets[std::size_t(edges[2])]);
        }
    }

    /// The leaf cell holding the unit cell with global minimum corner @a unit.
    CellView cell_of(const openvdb::Coord& unit) const {
        const openvdb::Coord origin(unit.x() & ~(kIfcBlock - 1), unit.y() & ~(kIfcBlock - 1), unit.z() & ~(kIfcBlock - 1));
        CellView view;
        view.min = unit;
        const openvdb::Coord offset = origin - s_.origin;  // within one block of ours: edges touch no farther
        // Offsets are whole blocks (-8, 0 or 8): an arithmetic shift divides them exactly.
        static_assert(kIfcBlock == 8, "a block is 2^3 cells");
        const IfcBlockCells* block = neighbour_[IfcCellGrid::neighbour_slot(offset.x() >> 3, offset.y() >> 3, offset.z() >> 3)];
        if (!block) return view;  // a block without surface: all unit cells
        const IfcBlockCells& cells = *block;
        const openvdb::Coord local = unit - origin;
        const int u = IfcBlockCells::unit_index(local.x(), local.y(), local.z());
        view.level = cells.level[u];
        view.size = 1 << view.level;
        view.min = openvdb::Coord(unit.x() & ~(view.size - 1), unit.y() & ~(view.size - 1), unit.z() & ~(view.size - 1));
        if (cells.cell[u] != IfcBlockCells::kNoCell) {
            view.vertex = &cells.cells[cells.cell[u]].vertex;
            view.feature = cells.cells[cells.cell[u]].feature;
        }
        return view;
    }

    struct Ring {
        std::array<CellView, 4> cell;
        /// Per cell: the quadrant (0..3, counter-clockwise) where it ends going round, so the
        /// face to the next cell lies between quadrants end and end + 1.
        std::array<int, 4> end;
        int count = 0;
    };

    void crossed_edge(int x, int y, int z, int axis) {
        const int u = (axis + 1) % 3, w = (axis + 2) % 3;
        const openvdb::Coord e = s_.origin.offsetBy(x, y, z);
        const std::uint64_t p_key = origin_key_ + (std::uint64_t(axis) << kPayloadShift) + key_offset(x, y, z);
        // Quadrants counter-clockwise round +axis (u x w = axis): (+,+), (-,+), (-,-), (+,-).
        static constexpr int kDu[4] = {0, -1, -1, 0}, kDw[4] = {0, 0, -1, -1};
        std::array<CellView, 4> quadrant;
        bool any_merged = false, any_unit = false;
        for (int q = 0; q < 4; ++q) {
            openvdb::Coord unit = e;
            unit[u] += kDu[q];
            unit[w] += kDw[q];
            quadrant[q] = cell_of(unit);
            any_merged |= quadrant[q].merged();
            any_unit |= !quadrant[q].merged();
        }
        // The crossing is a vertex where a Marching Cubes cell or the fan round it uses it;
        // inside merged cells it is not.
        const Point3d p = crossing_point(x, y, z, axis);
        if (any_unit) add_vertex(p_key, p);
        if (!any_merged) return;  // Marching Cubes all round
        // Counter-clockwise round the outward direction: from the inside end to the outside end.
        const bool outward_positive = s_.in(x, y, z);
        Ring ring;
        for (int step = 0; step < 4; ++step) {
            const int q = outward_positive ? step : (4 - step) % 4;
            if (ring.count > 0 && ring.cell[ring.count - 1] == quadrant[q]) {
                ring.end[ring.count - 1] = q;
                continue;
            }
            ring.cell[ring.count] = quadrant[q];
            ring.end[ring.count] = q;
            ++ring.count;
        }
        if (ring.count > 1 && ring.cell[ring.count - 1] == ring.cell[0]) --ring.count;  // wrapped round
        if (ring.count <= 2) return;  // inside a cell or a face: the cells' vertices stand for it
        if (try_polygon(ring, e, axis, p)) return;
        if (!any_unit) add_vertex(p_key, p);
        fan(ring, e, axis, outward_positive, p_key);
    }

    /// The crossing of the block's own crossed edge being walked (recorded in walk order).
    Point3d crossing_point(int x, int y, int z, int axis) const {
        Point3d p = to_point(s_.origin.offsetBy(x, y, z));
        p[axis] = (*crossings_)[next_crossing_];
        return p;
    }

    // ---- faces between two merged cells ----
    /// How the surface crosses the face between two merged cells: through the segment between
    /// their vertices (direct: triangles (p_e, v_a, v_b)), else along the chord of the face's two
    /// rim crossings p, q: (p, v_a, q), (p, q, v_b).
    struct FacePlan {
        bool direct = true;
        std::array<std::uint64_t, 2> chord_keys{};  ///< the crossings' keys, when not direct
    };
    /// The keys of the two crossed grid edges on the rim of the face [lo, hi] (flat along
    /// @a normal) of a merged cell: its face carries one open chain, whose ends they are.
    std::array<std::uint64_t, 2> rim_crossings(const Point3d& lo, const Point3d& hi, int normal) {
        const int u = (normal + 1) % 3, w = (normal + 2) % 3;
        std::array<std::uint64_t, 2> keys{};
        int count = 0;
        const openvdb::Coord corner{int(lo[0]), int(lo[1]), int(lo[2])};
        for (int along : {u, w}) {
            const int across = along == u ? w : u;
            for (int side = 0; side < 2; ++side) {
                for (int k = 0; k < int(hi[along] - lo[along]); ++k) {
                    openvdb::Coord start = corner;
                    start[along] += k;
                    start[across] += side * int(hi[across] - lo[across]);
                    const openvdb::Coord end = start.offsetBy(along == 0, along == 1, along == 2);
                    if (inside(start) == inside(end)) continue;
                    if (count < 2) keys[count] = edge_key(start, along);
                    ++count;
                }
            }
        }
        if (count != 2) throw Error("contouring: the face between two merged cells has " + std::to_string(count) + " crossed rim edges, not 2");
        return keys;
    }

    /// Whether grid point @a ijk is inside: from the rows of bits in the block's window, else
    /// from the grid.
    bool inside(const openvdb::Coord& ijk) {
        const openvdb::Coord local = ijk - s_.origin;
        if (local.x() >= -1 && local.x() <= kIfcBlock + 1 && local.y() >= -1 && local.y() <= kIfcBlock + 1 &&
            local.z() >= -1 && local.z() <= kIfcBlock + 1) {
            return s_.in(local.x(), local.y(), local.z());
        }
        return classifier_.inside(classifier_.sample_value(ijk, accessor_.getValue(ijk)));
    }

    /// The face shared by merged cells @a a and @a b, decided the same whichever edge asks.
    FacePlan face_plan(const CellView& a_in, const CellView& b_in) {
        const bool swap = b_in.key() < a_in.key();
        const CellView& a = swap ? b_in : a_in;
        const CellView& b = swap ? a_in : b_in;
        Point3d lo, hi;
        int normal = 0;
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::max(a.min[k], b.min[k]);
            hi[k] = std::min(a.min[k] + a.size, b.min[k] + b.size);
            if (lo[k] == hi[k]) normal = k;
        }
        const Point3d& va = *a.vertex;
        const Point3d& vb = *b.vertex;
        const double t = (lo[normal] - va[normal]) / (vb[normal] - va[normal]);
        FacePlan plan;
        for (int k = 0; k < 3; ++k) {
            if (k == normal) continue;
            const double x = va[k] + t * (vb[k] - va[k]);
            if (!(x > lo[k] + kIfcInteriorMargin && x < hi[k] - kIfcInteriorMargin)) plan.direct = false;
        }
        if (!plan.direct) plan.chord_keys = rim_crossings(lo, hi, normal);
        return plan;
    }

    /// The polygon of the ring's merged cells, without the edge's @a crossing: every face test,
    /// the edge test and the accuracy test (polygon_near()) must pass.
    bool try_polygon(const Ring& ring, const openvdb::Coord& e, int axis, const Point3d& crossing) {
        for (int i = 0; i < ring.count; ++i) {
            if (!ring.cell[i].merged()) return false;
        }
        for (int i = 0; i < ring.count; ++i) {
            if (!face_plan(ring.cell[i], ring.cell[(i + 1) % ring.count]).direct) return false;
        }
        // The minimal edge: the part of the grid line all the ring's cells touch.
        Point3d e0 = to_point(e), e1 = e0;
        e0[axis] = -1e300;
        e1[axis] = 1e300;
        for (int i = 0; i < ring.count; ++i) {
            e0[axis] = std::max(e0[axis], double(ring.cell[i].min[axis]));
            e1[axis] = std::min(e1[axis], double(ring.cell[i].min[axis] + ring.cell[i].size));
        }
        std::array<const Point3d*, 4> v;
        for (int i = 0; i < ring.count; ++i) v[i] = ring.cell[i].vertex;
        const double sigma = orient(e0, e1, *v[0], *v[1]) > 0 ? 1.0 : -1.0;
        for (int i = 0; i < ring.count; ++i) {
            if (sigma * orient(e0, e1, *v[i], *v[(i + 1) % ring.count]) <= kOrientationFloor) return false;
        }
        // Fans from corner 0, or (a quadrilateral) from corner 1: the shorter diagonal first.
        std::array<int, 2> starts = {0, 1};
        if (ring.count == 4 && squared_distance(*v[1], *v[3]) < squared_distance(*v[0], *v[2])) std::swap(starts[0], starts[1]);
        const int tries = ring.count == 4 ? 2 : 1;
        for (int t = 0; t < tries; ++t) {
            const int s = starts[t];
            bool valid = true;
            for (int j = 1; j + 1 < ring.count && valid; ++j) {
                const Point3d& a = *v[s];
                const Point3d& b = *v[(s + j) % ring.count];
                const Point3d& c = *v[(s + j + 1) % ring.count];
                valid = sigma * orient(e0, a, b, c) > kOrientationFloor && -sigma * orient(e1, a, b, c) > kOrientationFloor;
            }
            if (!valid || !polygon_near(ring, s, crossing)) continue;
            for (int j = 1; j + 1 < ring.count; ++j) {
                add_triangle(ring.cell[s].key(), ring.cell[(s + j) % ring.count].key(), ring.cell[(s + j + 1) % ring.count].key());
            }
            return true;
        }
        return false;
    }

    /// Whether the edge's crossing lies within the error of the polygon triangulated from
    /// corner @a s. The merges' accuracy tests take a crossing on a cell's edge as a vertex of
    /// the cell's fan; the polygon drops it, so it is held to the error here (without this, the
    /// CThead at --error 1 lost the tip of a thin wall, 1.72 voxels short; with it, 14 more
    /// triangles). Round a `--sharp` feature point the crossing lies on the rounded trilinear
    /// isosurface, which the feature leaves by up to kSharpReach more (dc_qef.h).
    bool polygon_near(const Ring& ring, int s, const Point3d& crossing) const {
        bool feature = false;
        for (int i = 0; i < ring.count; ++i) feature |= ring.cell[i].feature;
        const double reach = error_ + (feature ? kSharpReach : 0.0);
        const double limit = reach * reach;
        for (int j = 1; j + 1 < ring.count; ++j) {
            const Point3d q = closest_point_on_triangle(crossing, *ring.cell[s].vertex, *ring.cell[(s + j) % ring.count].vertex,
                                                        *ring.cell[(s + j + 1) % ring.count].vertex);
            if (squared_distance(q, crossing) <= limit) return true;
        }
        return false;
    }

    /// The other crossed edge of the unit face between quadrants @a q and @a q + 1 round edge @a e.
    std::uint64_t partner_on_unit_face(const openvdb::Coord& e, int axis, int q, bool outward_positive) const {
        const int u = (axis + 1) % 3, w = (axis + 2) % 3;
        // Between quadrants q and the next one going round (in the ring's direction).
        const int next = outward_positive ? (q + 1) % 4 : (q + 3) % 4;
        static constexpr int kDu[4] = {0, -1, -1, 0}, kDw[4] = {0, 0, -1, -1};
        // The two quadrants share their offset along the face's in-plane perpendicular axis.
        const bool same_u = kDu[q] == kDu[next];
        const int across = same_u ? u : w;  // in the face, perpendicular to the edge
        const int offset = same_u ? kDu[q] : kDw[q];
        openvdb::Coord origin = e;
        origin[across] += offset;
        // The face's four edges: along axis at origin and origin + across; along across at
        // origin and origin + axis.
        std::array<std::pair<openvdb::Coord, int>, 4> edges;
        edges[0] = {origin, axis};
        edges[1] = {origin, axis};
        edges[1].first[across] += 1;
        edges[2] = {origin, across};
        edges[3] = {origin, across};
        edges[3].first[axis] += 1;
        const std::uint64_t own = edge_key(e, axis);
        for (const auto& [start, dir] : edges) {
            const openvdb::Coord local = start - s_.origin;
            if (!s_.crossed(local.x(), local.y(), local.z(), dir)) continue;
            const std::uint64_t key = edge_key(start, dir);
            if (key != own) return key;
        }
        throw Error("contouring: a unit face next to a merged cell has one crossed edge");
    }

    /// The fan round the edge's crossing @a p.
    void fan(const Ring& ring, const openvdb::Coord& e, int axis, bool outward_positive, std::uint64_t p) {
        for (int i = 0; i < ring.count; ++i) {
            const CellView& a = ring.cell[i];
            const CellView& b = ring.cell[(i + 1) % ring.count];
            if (a.merged() && b.merged()) {
                const FacePlan plan = face_plan(a, b);
                if (plan.direct) {
                    add_triangle(p, a.key(), b.key());
                    continue;
                }
                // The face's two triangles over the chord p q, made once, from the crossing
                // with the smaller key.
                if (plan.chord_keys[0] != p && plan.chord_keys[1] != p) throw Error("contouring: a face's chord misses the edge round which it is made");
                const std::uint64_t q = plan.chord_keys[0] == p ? plan.chord_keys[1] : plan.chord_keys[0];
                if (q < p) continue;
                add_triangle(p, a.key(), q);
                add_triangle(p, q, b.key());
            } else if (a.merged() || b.merged()) {
                // The unit cell's face holds the surface's segment p-q; the triangle over it
                // is made once, from the edge with the smaller key.
                const std::uint64_t q = partner_on_unit_face(e, axis, ring.end[i], outward_positive);
                if (q < p) continue;
                if (a.merged()) add_triangle(p, a.key(), q);
                else add_triangle(p, q, b.key());
            }
        }
    }

    const IfcSamples& s_;
    std::array<const IfcBlockCells*, 27> neighbour_;  ///< the blocks round this one (index 13), or null
    const SampleClassifier& classifier_;
    openvdb::FloatGrid::ConstAccessor& accessor_;
    const IfcCellGrid& grid_;
    std::size_t block_;
    double error_;
    const openvdb::math::Transform& transform_;
    IfcBlockOutput& out_;
    std::uint64_t origin_key_ = 0;  ///< edge_key() of the block's origin along x
    const std::vector<double>* crossings_ = nullptr;
    std::size_t next_crossing_ = 0;  ///< index in crossings_ of the crossed edge being walked
};

}  // namespace

bool ifc_key_of_coarse_cell(std::uint64_t key) {
    return (key >> kKindShift) == kCellKind && ((key >> kPayloadShift) & 31u) > unsigned(kIfcMaxLevel);
}

openvdb::Coord ifc_key_point(std::uint64_t key) {
    constexpr std::uint64_t kMask = (std::uint64_t(1) << kCoordBits) - 1;
    openvdb::Coord p;
    for (int a = 0; a < 3; ++a) p[a] = int(std::int64_t((key >> (kCoordBits * (2 - a))) & kMask) - kCoordBias);
    return p;
}

std::uint64_t ifc_edge_key(const openvdb::Coord& min_sample, int axis) {
    check_key_range(min_sample);
    return edge_key(min_sample, axis);
}

void contour_ifc_block(const SampleClassifier& classifier, openvdb::FloatGrid::ConstAccessor& accessor, const IfcCellGrid& grid,
                       std::size_t block, double error, const openvdb::math::Transform& transform, IfcBlockOutput& out) {
    thread_local IfcSamples rows;  // the rows of bits only: the contour reads no value
    const IfcBlockCells& cells = grid.block(block);
    rows.origin = grid.origins[block];
    rows.inside_rows = cells.inside_rows;
    BlockContour(rows, classifier, accessor, grid, block, error, transform, out).run();
}

}  // namespace vdbmesh::detail
