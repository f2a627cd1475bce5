// Polygons of intersection-free octree contouring, after Ju and Udeshi, "Intersection-free
// Contouring on an Octree Grid" (Pacific Graphics 2006), with Marching Cubes in unit cells.
//
// Why no two triangles cross. Every merged cell C is cut into pyramids from its vertex v_C
// (strictly inside C) over its minimal faces, and each pyramid over a face f shared with
// another merged cell into tetrahedra (v_C, x_f, e) over the minimal edges e of f, where x_f
// is a point strictly inside f. Unit cells stay whole. Each triangle lies in one of these
// pieces, or in the union of the pieces around one edge, and pieces meet only on their
// boundaries, where the triangles share their edges:
//  - unit cells: Marching Cubes triangles, inside the cube;
//  - a merged cell C next to a unit cell across unit face f: the triangle (v_C, p_e, p_q) over
//    the surface's segment on f, inside the pyramid (v_C, f);
//  - a crossed minimal edge e with a merged cell on some side: the fan around its crossing
//    p_e: (p_e, v_i, v_i+1) when the segment v_i v_i+1 passes strictly inside their face
//    (the face test; x_f is that crossing, and the triangle lies in the tetrahedron
//    (e, v_i, v_i+1)), else (p_e, v_i, m_f), (p_e, m_f, v_i+1) with a face point m_f, or,
//    where the surface crosses the rim of their face f at p_e and one more crossing q,
//    (p_e, v_i, q) and (p_e, q, v_i+1) over the chord p_e q, inside the pyramids (v_i, f) and
//    (v_i+1, f), which then hold no other triangle (no face point cuts them): whichever of the
//    two has the larger smallest angle (a face point next to a crossing is a sliver);
//  - the same edge with only merged cells around it and every face test passed: the polygon
//    v_1..v_k without p_e, triangulated from one corner, when the flip of the tetrahedra
//    (e, v_i, v_i+1) into (e_0 | e_1, v_1, v_j, v_j+1) keeps every orientation (the edge
//    test): the new tetrahedra then tile the same region, and the triangles are their faces.
// The tests use a margin far above the float rounding of the output (kIfcInteriorMargin,
// kOrientationFloor), so what holds in double holds for the written floats.

#include "mesh/ifc_polygons.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "mesh/ifc_fan.h"
#include "mesh/mc_table.h"
#include "vdbmesh/error.h"

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
            found[std::size_t(column * 3 + dz)] = here ? it - origins.begin() : -1;
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

/// Largest distance (voxels) a crossing is moved along its edge away from the nearer sample.
constexpr double kMaxCrossingMargin = 0.25;

// ---- Vertex keys: kind (2 bits), payload (5 bits), x, y, z (19 bits each, biased) ----
constexpr int kCoordBits = 19;
constexpr std::int64_t kCoordBias = std::int64_t(1) << (kCoordBits - 1);

std::uint64_t make_key(unsigned kind, unsigned payload, const openvdb::Coord& p) {
    std::uint64_t key = (std::uint64_t(kind) << 62) | (std::uint64_t(payload) << 57);
    for (int a = 0; a < 3; ++a) {
        const std::int64_t c = std::int64_t(p[a]) + kCoordBias;
        if (c < 0 || c >= (std::int64_t(1) << kCoordBits)) throw Error("contouring: grid coordinates beyond +-2^18");
        key |= std::uint64_t(c) << (kCoordBits * (2 - a));
    }
    return key;
}
std::uint64_t edge_key(const openvdb::Coord& min_sample, int axis) { return make_key(0, unsigned(axis), min_sample); }

/// A leaf cell of the octree as seen from an edge: a unit Marching Cubes cell or a merged cell.
struct CellView {
    openvdb::Coord min;
    int size = 1;
    int level = 0;
    const Point3d* vertex = nullptr;  ///< merged cells
    bool merged() const { return vertex != nullptr; }
    bool operator==(const CellView& o) const { return min == o.min && size == o.size; }
    std::uint64_t key() const { return make_key(1, unsigned(level), min); }
};

Point3d to_point(const openvdb::Coord& c) { return {double(c.x()), double(c.y()), double(c.z())}; }

double orient(const Point3d& a, const Point3d& b, const Point3d& c, const Point3d& d) {
    const double b0 = b[0] - a[0], b1 = b[1] - a[1], b2 = b[2] - a[2];
    const double c0 = c[0] - a[0], c1 = c[1] - a[1], c2 = c[2] - a[2];
    const double d0 = d[0] - a[0], d1 = d[1] - a[1], d2 = d[2] - a[2];
    return b0 * (c1 * d2 - c2 * d1) - b1 * (c0 * d2 - c2 * d0) + b2 * (c0 * d1 - c1 * d0);
}

Point3d lerp(const Point3d& a, const Point3d& b, double t) {
    return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

double squared_distance(const Point3d& a, const Point3d& b) {
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

double distance_to_segment(const Point3d& p, const Point3d& a, const Point3d& b) {
    const double length2 = squared_distance(a, b);
    double t = 0;
    if (length2 > 0) t = ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1]) + (p[2] - a[2]) * (b[2] - a[2])) / length2;
    return std::sqrt(squared_distance(p, lerp(a, b, std::clamp(t, 0.0, 1.0))));
}

/// The smallest angle of triangle (a, b, c), degrees (0 when degenerate).
double smallest_angle(const Point3d& a, const Point3d& b, const Point3d& c) {
    const Point3d* p[3] = {&a, &b, &c};
    double smallest = 180;
    for (int k = 0; k < 3; ++k) {
        const Point3d& o = *p[k];
        const Point3d& q = *p[(k + 1) % 3];
        const Point3d& r = *p[(k + 2) % 3];
        const double lq = std::sqrt(squared_distance(o, q)), lr = std::sqrt(squared_distance(o, r));
        if (lq == 0 || lr == 0) return 0;
        const double c = ((q[0] - o[0]) * (r[0] - o[0]) + (q[1] - o[1]) * (r[1] - o[1]) + (q[2] - o[2]) * (r[2] - o[2])) / (lq * lr);
        smallest = std::min(smallest, std::acos(std::clamp(c, -1.0, 1.0)) * 180 / 3.14159265358979323846);
    }
    return smallest;
}

class BlockContour {
public:
    BlockContour(const IfcSamples& s, const SampleClassifier& classifier, openvdb::FloatGrid::ConstAccessor& accessor,
                 const IfcCellGrid& grid, std::size_t block, const openvdb::math::Transform& transform, double error,
                 IfcBlockOutput& out)
        : s_(s), classifier_(classifier), accessor_(accessor), iso_(classifier.iso()), error_(error), crossing_margin_(std::min(error, kMaxCrossingMargin)), grid_(grid), block_(block),
          transform_(transform), out_(out) {}

    void run() {
        const std::array<std::ptrdiff_t, 27> around = grid_.neighbours(block_);
        for (int n = 0; n < 27; ++n) neighbour_[n] = around[n] < 0 ? nullptr : &grid_.block(std::size_t(around[n]));
        const IfcBlockCells& cells = grid_.block(block_);
        for (const IfcCell& cell : cells.cells) add_vertex(make_key(1, cell.level, cell.min), cell.vertex);
        // Per unit cell in order: its Marching Cubes triangles when it is a unit cell, then its
        // three crossed edges; rows of bits skip the cells and edges without surface.
        static constexpr unsigned kBlockBits = ((1u << kIfcBlock) - 1) << 1;  // z = 0..7 at bits 1..8
        for (int x = 0; x < kIfcBlock; ++x) {
            for (int y = 0; y < kIfcBlock; ++y) {
                const unsigned mixed = s_.mixed_cells_row(x, y) & kBlockBits;
                const std::array<unsigned, 3> along = {s_.crossed_row(x, y, 0) & kBlockBits, s_.crossed_row(x, y, 1) & kBlockBits,
                                                       s_.crossed_row(x, y, 2) & kBlockBits};
                for (unsigned any = mixed | along[0] | along[1] | along[2]; any != 0; any &= any - 1) {
                    const int z = __builtin_ctz(any) - 1;
                    if (((mixed >> (z + 1)) & 1u) && cells.level[IfcBlockCells::unit_index(x, y, z)] == 0) marching_cube(x, y, z);
                    for (int axis = 0; axis < 3; ++axis) {
                        if ((along[axis] >> (z + 1)) & 1u) crossed_edge(x, y, z, axis);
                    }
                }
            }
        }
    }

private:
    void add_vertex(std::uint64_t key, const Point3d& index_point) {
        const openvdb::Vec3d w = transform_.indexToWorld(openvdb::Vec3d(index_point[0], index_point[1], index_point[2]));
        out_.vertices.push_back({key, {float(w[0]), float(w[1]), float(w[2])}});
    }
    void add_triangle(std::uint64_t a, std::uint64_t b, std::uint64_t c) { out_.triangles.push_back({a, b, c}); }

    void marching_cube(int x, int y, int z) {
        const McCase& c = mc_case(s_.config(x, y, z));
        for (int t = 0; t < c.triangle_count; ++t) {
            std::array<std::uint64_t, 3> keys;
            for (int k = 0; k < 3; ++k) {
                const unsigned c0 = kEdgeCorners[c.triangles[t][k]][0], c1 = kEdgeCorners[c.triangles[t][k]][1];
                const int axis = (c0 ^ c1) == 1 ? 0 : (c0 ^ c1) == 2 ? 1 : 2;
                keys[k] = edge_key(s_.origin.offsetBy(x + int(c0 & 1), y + int((c0 >> 1) & 1), z + int(c0 >> 2)), axis);
            }
            add_triangle(keys[0], keys[1], keys[2]);
        }
    }

    /// The leaf cell holding the unit cell with global minimum corner @a unit.
    CellView cell_of(const openvdb::Coord& unit) const {
        const openvdb::Coord origin(unit.x() & ~(kIfcBlock - 1), unit.y() & ~(kIfcBlock - 1), unit.z() & ~(kIfcBlock - 1));
        CellView view;
        view.min = unit;
        const openvdb::Coord offset = origin - s_.origin;  // within one block of ours: edges touch no farther
        const IfcBlockCells* block = neighbour_[(offset.x() / kIfcBlock + 1) * 9 + (offset.y() / kIfcBlock + 1) * 3 + offset.z() / kIfcBlock + 1];
        if (!block) return view;  // a block without surface: all unit cells
        const IfcBlockCells& cells = *block;
        const openvdb::Coord local = unit - origin;
        const int u = IfcBlockCells::unit_index(local.x(), local.y(), local.z());
        view.level = cells.level[u];
        view.size = 1 << view.level;
        view.min = openvdb::Coord(unit.x() & ~(view.size - 1), unit.y() & ~(view.size - 1), unit.z() & ~(view.size - 1));
        if (cells.cell[u] != IfcBlockCells::kNoCell) view.vertex = &cells.cells[cells.cell[u]].vertex;
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
        const std::uint64_t p_key = edge_key(e, axis);
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
        if (any_unit) add_vertex(p_key, crossing_point(x, y, z, axis));
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
        if (try_polygon(ring, e, axis)) return;
        if (!any_unit) add_vertex(p_key, crossing_point(x, y, z, axis));
        fan(ring, e, axis, outward_positive, p_key);
    }

    Point3d crossing_point(int x, int y, int z, int axis) const {
        const Point3d p0 = to_point(s_.origin.offsetBy(x, y, z));
        Point3d p1 = p0;
        p1[axis] += 1;
        return edge_crossing(p0, s_.at(x, y, z), p1, s_.at(x + (axis == 0), y + (axis == 1), z + (axis == 2)), iso_, crossing_margin_);
    }

    // ---- faces between two merged cells ----
    /// How the surface crosses the face between two merged cells.
    enum class FaceKind {
        direct,      ///< the segment between the vertices crosses the face inside: triangles (p_e, v_a, v_b)
        face_point,  ///< through a face point m_f: (p_e, v_a, m_f), (p_e, m_f, v_b)
        chord,       ///< along the chord of the face's two crossings p, q: (p, v_a, q), (p, q, v_b)
    };
    struct FacePlan {
        FaceKind kind = FaceKind::direct;
        bool direct() const { return kind == FaceKind::direct; }
        std::uint64_t key = 0;  ///< the face point's
        Point3d point{};
        std::array<std::uint64_t, 2> chord_keys{};  ///< the crossings' (FaceKind::chord)
    };
    struct Chord {
        std::array<Point3d, 2> ends;
        std::array<std::uint64_t, 2> keys;
    };

    /// The crossings (and their keys) of the two crossed grid edges on the perimeter of the face
    /// [lo, hi] (flat along @a normal); none unless there are exactly two.
    std::optional<Chord> chord_ends(const Point3d& lo, const Point3d& hi, int normal) {
        const int u = (normal + 1) % 3, w = (normal + 2) % 3;
        Chord chord;
        int count = 0;
        auto visit = [&](openvdb::Coord start, int axis) {
            const openvdb::Coord end = start.offsetBy(axis == 0, axis == 1, axis == 2);
            const double f0 = sample(start), f1 = sample(end);
            if (classifier_.inside(f0) == classifier_.inside(f1)) return;
            if (count < 2) {
                chord.ends[count] = edge_crossing(to_point(start), f0, to_point(end), f1, iso_, crossing_margin_);
                chord.keys[count] = edge_key(start, axis);
            }
            ++count;
        };
        const openvdb::Coord corner{int(lo[0]), int(lo[1]), int(lo[2])};
        for (int along : {u, w}) {
            const int across = along == u ? w : u;
            for (int side = 0; side < 2; ++side) {
                for (int k = 0; k < int(hi[along] - lo[along]); ++k) {
                    openvdb::Coord start = corner;
                    start[along] += k;
                    start[across] += side * int(hi[across] - lo[across]);
                    visit(start, along);
                }
            }
        }
        if (count != 2) return std::nullopt;
        return chord;
    }

    /// The face point for the fans of the chord @a ends between the vertices @a va and @a vb:
    /// of points between the chord's midpoint and @a through (where the segment va-vb meets the
    /// face, clamped into it), no farther than the error from the chord and no farther from the
    /// surface than the midpoint (first-order distance in the trilinear field), the one whose
    /// four triangles (a chord end, a vertex, the point) have the largest smallest angle; then
    /// kept the interior margin inside the face [lo, hi] (flat along @a normal), which is convex.
    Point3d face_point(const std::array<Point3d, 2>& ends, const Point3d& through, const Point3d& va, const Point3d& vb,
                       const Point3d& lo, const Point3d& hi, int normal, double& smallest) {
        const Point3d mid = lerp(ends[0], ends[1], 0.5);
        const double mid_distance = surface_distance(mid);
        Point3d best = mid;
        double best_angle = -1;
        for (const double t : {0.0, 0.25, 0.5, 0.75, 1.0}) {
            const Point3d m = lerp(mid, through, t);
            if (t > 0 && distance_to_segment(m, ends[0], ends[1]) > error_) break;
            if (t > 0 && surface_distance(m) > mid_distance) continue;
            double angle = 180;
            for (const Point3d& e : ends) angle = std::min({angle, smallest_angle(e, va, m), smallest_angle(e, m, vb)});
            if (angle > best_angle) {
                best_angle = angle;
                best = m;
            }
        }
        for (int k = 0; k < 3; ++k) {
            best[k] = k == normal ? lo[k] : std::clamp(best[k], lo[k] + kIfcInteriorMargin, hi[k] - kIfcInteriorMargin);
        }
        smallest = 180;
        for (const Point3d& e : ends) smallest = std::min({smallest, smallest_angle(e, va, best), smallest_angle(e, best, vb)});
        return best;
    }

    /// First-order distance (voxels) from @a p to the trilinear isosurface of the unit cell holding it.
    double surface_distance(const Point3d& p) {
        const std::array<int, 3> cell = {int(std::floor(p[0])), int(std::floor(p[1])), int(std::floor(p[2]))};
        return cell_surface_distance(p, cell, [&](int x, int y, int z) { return sample(openvdb::Coord(x, y, z)); }, iso_);
    }

    /// The value meshers use at grid point @a ijk.
    double sample(const openvdb::Coord& ijk) {
        const openvdb::Coord local = ijk - s_.origin;
        if (local.x() >= -1 && local.x() <= kIfcBlock + 1 && local.y() >= -1 && local.y() <= kIfcBlock + 1 &&
            local.z() >= -1 && local.z() <= kIfcBlock + 1) {
            return s_.at(local.x(), local.y(), local.z());
        }
        return classifier_.sample_value(ijk, accessor_.getValue(ijk));
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
            if (k == normal) {
                plan.point[k] = lo[k];
                continue;
            }
            const double x = va[k] + t * (vb[k] - va[k]);
            if (!(x > lo[k] + kIfcInteriorMargin && x < hi[k] - kIfcInteriorMargin)) plan.kind = FaceKind::face_point;
            plan.point[k] = std::clamp(x, lo[k] + kIfcInteriorMargin, hi[k] - kIfcInteriorMargin);
        }
        if (!plan.direct()) {
            // Near the chord of the surface's trace across the face (the clamped crossing
            // alone can be a face's width away from the surface), or along the chord itself,
            // whichever makes the larger smallest angle: a face point close to a crossing
            // makes a sliver with the far vertex.
            const std::optional<Chord> chord = chord_ends(lo, hi, normal);
            if (chord) {
                double face_point_angle = 0;
                plan.point = face_point(chord->ends, plan.point, va, vb, lo, hi, normal, face_point_angle);
                const double chord_angle =
                    std::min(smallest_angle(chord->ends[0], va, chord->ends[1]), smallest_angle(chord->ends[0], chord->ends[1], vb));
                if (chord_angle >= face_point_angle) {
                    plan.kind = FaceKind::chord;
                    plan.chord_keys = chord->keys;
                    return plan;
                }
            }
            // Named by the smaller cell (the face is one of its faces: leaves do not nest, so
            // its minimum corner names it) and the side it faces.
            const CellView& owner = a.size <= b.size ? a : b;
            const CellView& other = a.size <= b.size ? b : a;
            const bool positive = other.min[normal] >= owner.min[normal] + owner.size;
            plan.key = make_key(2, unsigned(normal * 2 + positive), owner.min);
            add_vertex(plan.key, plan.point);
        }
        return plan;
    }

    /// The polygon of the ring's merged cells, without the edge's crossing: every face test
    /// and the edge test must pass.
    bool try_polygon(const Ring& ring, const openvdb::Coord& e, int axis) {
        for (int i = 0; i < ring.count; ++i) {
            if (!ring.cell[i].merged()) return false;
        }
        for (int i = 0; i < ring.count; ++i) {
            if (!face_plan(ring.cell[i], ring.cell[(i + 1) % ring.count]).direct()) return false;
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
            if (!valid) continue;
            for (int j = 1; j + 1 < ring.count; ++j) {
                add_triangle(ring.cell[s].key(), ring.cell[(s + j) % ring.count].key(), ring.cell[(s + j + 1) % ring.count].key());
            }
            return true;
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
                if (plan.kind == FaceKind::direct) {
                    add_triangle(p, a.key(), b.key());
                } else if (plan.kind == FaceKind::face_point) {
                    add_triangle(p, a.key(), plan.key);
                    add_triangle(p, plan.key, b.key());
                } else {
                    // The face's two triangles, made once, from the crossing with the smaller key.
                    if (plan.chord_keys[0] != p && plan.chord_keys[1] != p) throw Error("contouring: a face's chord misses the edge round which it is made");
                    const std::uint64_t q = plan.chord_keys[0] == p ? plan.chord_keys[1] : plan.chord_keys[0];
                    if (q < p) continue;
                    add_triangle(p, a.key(), q);
                    add_triangle(p, q, b.key());
                }
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
    double iso_;
    double error_;
    double crossing_margin_;  ///< of the edge's length, kept between a crossing and the edge's ends
    const IfcCellGrid& grid_;
    std::size_t block_;
    const openvdb::math::Transform& transform_;
    IfcBlockOutput& out_;
};

}  // namespace

void contour_ifc_block(const IfcSamples& samples, const SampleClassifier& classifier,
                       openvdb::FloatGrid::ConstAccessor& accessor, const IfcCellGrid& grid, std::size_t block,
                       const openvdb::math::Transform& transform, double error, IfcBlockOutput& out) {
    BlockContour(samples, classifier, accessor, grid, block, transform, error, out).run();
}

}  // namespace vdbmesh::detail
