// decimate_mesh(): quadric edge collapse (M. Garland and P. Heckbert, SIGGRAPH 1997) that keeps a
// closed manifold mesh closed, manifold, oriented and free of self-intersections.
//
// The collapses are made in rounds. Each round takes the cheapest edges (about as many as
// collapses are still wanted) and picks among them, in order of cost, those whose ends lie in the
// star of no edge picked before (as meshoptimizer locks vertices). Those are checked in parallel
// against the mesh as it was at the start of the round, then applied in order of cost. No collapse
// of the round changes what another's checks read (its ends' rings, its star) but for the new
// triangles of two collapses: those crossings are found in parallel too, between the new stars as
// the checks built them, and a plan crossing one applied before it waits. So the result does not
// depend on the thread count. Each collapse is checked where it changes the mesh, on the float
// coordinates that will be written:
// - topology: the link condition (the ends' neighbours in common are exactly the two opposite
//   corners; T. K. Dey et al., "Topology preserving edge contraction", 1999), which keeps a
//   closed 2-manifold one;
// - geometry: no triangle of the new star is degenerate (exact collinearity) or turns by more
//   than kMaxTurnDegrees, and no component's enclosed volume changes sign (a nearly flat speck
//   can turn inside out while each triangle turns little; checked in the sequential apply, on
//   each component's volume kept up to date by the collapses' changes);
// - intersections: most collapses are cleared without a test between triangles, when all the
//   triangles near them and their new ones face a common direction (the proof is at
//   intersection_free()): the grids' cells keep what their triangles have in common. The others:
//   each new triangle against the others of the star and against the triangles the grids find
//   near it (one of all triangles, rebuilt once a quarter of them has moved, and one of those
//   moved since, rebuilt each round), with the exact tests of `vdbmesh check`; a plane that
//   certainly separates the two triangles (vdbmesh/separating_plane.h) spares most of them.
//   The same holds for the crossings between two new stars of a round.
// The mesh is held as a corner table (each corner's opposite corner across its edge), flat arrays
// throughout.
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

#include "vdbmesh/separating_plane.h"
#include "process/quadric.h"
#include "vdbmesh/error.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/process.h"
#include "vdbmesh/union_find.h"

namespace vdbmesh {
namespace {

using detail::Quadric;
using detail::Vec3d;
using Ids = std::array<std::uint32_t, 3>;
using Box = detail::Box;

constexpr std::uint32_t kNone = ~0u;
constexpr double kMaxTurnDegrees = 75;  ///< largest change of a triangle's normal in one collapse
const double kMinTurnCosine = std::cos(kMaxTurnDegrees * 3.14159265358979323846 / 180);
/// Ties of the quadric error (flat regions, where it is 0) go to the shorter edge, which keeps
/// the triangles there from growing into needles.
constexpr double kLengthWeight = 1e-3;
constexpr double kNever = std::numeric_limits<double>::infinity();  ///< the cost of an edge that may not collapse
constexpr std::size_t kCellsPerBox = 8;  ///< a grid has at most about this many cells per box
constexpr double kCellEdges = 1;       ///< triangle grid cell size in mean triangle extents
constexpr std::size_t kMinRound = 64;  ///< candidates a round takes at least
/// ... and at least this share of the triangles: near the target a round applies only about a
/// fifth of the few collapses still wanted, and every round costs passes over the whole mesh
/// (CThead: 38 rounds without, 19 with, the largest quadric error 1% higher).
constexpr std::size_t kMinRoundDivisor = 32;

Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3d cross(const Vec3d& a, const Vec3d& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3d to_double(const std::array<float, 3>& p) { return {p[0], p[1], p[2]}; }
std::array<float, 3> to_float(const Vec3d& p) { return {float(p[0]), float(p[1]), float(p[2])}; }
using FloatTriangle = std::array<std::array<float, 3>, 3>;
detail::Triangle3 to_double(const FloatTriangle& t) { return {to_double(t[0]), to_double(t[1]), to_double(t[2])}; }

std::uint32_t next(std::uint32_t c) { return c % 3 == 2 ? c - 2 : c + 1; }
std::uint32_t prev(std::uint32_t c) { return c % 3 == 0 ? c + 2 : c - 1; }

Box empty_box() {
    constexpr float inf = std::numeric_limits<float>::infinity();
    return {{inf, inf, inf}, {-inf, -inf, -inf}};
}
bool holds_nothing(const Box& box) { return !(box.lo[0] <= box.hi[0]); }  ///< (as empty_box())
void grow(Box& box, const std::array<float, 3>& p) {
    for (int k = 0; k < 3; ++k) box.lo[k] = std::min(box.lo[k], p[k]), box.hi[k] = std::max(box.hi[k], p[k]);
}

void check_closed_manifold(const Mesh& mesh) {
    const detail::Topology topology = detail::analyze_topology(mesh);
    if (topology.boundary_edges || topology.nonmanifold_edges || topology.nonmanifold_vertices || topology.misoriented_edges) {
        throw Error("decimate: expected a closed, manifold, consistently oriented mesh, got " +
                    std::to_string(topology.boundary_edges) + " boundary edges, " + std::to_string(topology.nonmanifold_edges) +
                    " non-manifold edges, " + std::to_string(topology.nonmanifold_vertices) + " non-manifold vertices, " +
                    std::to_string(topology.misoriented_edges) + " misoriented edges");
    }
}

/// What the triangles in a part of space have in common: the directions they all face and the
/// component they all belong to (kNone: no triangle; kMixed: more than one).
struct Summary {
    static constexpr std::uint32_t kMixed = kNone - 1;
    std::uint32_t facing = ~0u;  ///< bit k: direction k of kDirections
    std::uint32_t component = kNone;
    void add(const Summary& o) {
        facing &= o.facing;
        component = component == kNone ? o.component : o.component == kNone || o.component == component ? component : kMixed;
    }
    /// Whether triangles with this in common clear a collapse (intersection_free()'s proof):
    /// they all face a common direction, in one component.
    bool clears() const { return component != kMixed && facing != 0; }
};

/// 32 directions spread evenly over the sphere (a golden-angle spiral).
const std::array<Vec3d, 32> kDirections = [] {
    std::array<Vec3d, 32> directions{};
    for (std::size_t k = 0; k < directions.size(); ++k) {
        const double z = 1 - (2 * double(k) + 1) / double(directions.size()), r = std::sqrt(1 - z * z), phi = double(k) * 2.399963229728653;
        directions[k] = {r * std::cos(phi), r * std::sin(phi), z};
    }
    return directions;
}();

/// The directions of kDirections that every normal in a part of the sphere faces, for normals
/// binned by the cube face their largest component points to and a kBins x kBins square there.
class FacingTable {
public:
    static constexpr int kBins = 16;

    FacingTable() {
        for (int face = 0; face < 6; ++face) {
            for (int i = 0; i < kBins; ++i) {
                for (int j = 0; j < kBins; ++j) table_[(face * kBins + i) * kBins + j] = facing_all(face, i, j);
            }
        }
    }

    /// The directions that @a n certainly faces (the triangle's normal, from edges whose
    /// squared lengths multiply to @a scale_squared): none when it is so short that its rounding
    /// (2^-49 times the edges' lengths at most) could turn it by more than 1e-6.
    std::uint32_t facing(const Vec3d& n, double scale_squared) const {
        const double m[3] = {std::abs(n[0]), std::abs(n[1]), std::abs(n[2])};
        const int axis = m[0] >= m[1] && m[0] >= m[2] ? 0 : m[1] >= m[2] ? 1 : 2;
        if (!(m[axis] * m[axis] > 1e-12 * scale_squared)) return 0;
        const int face = 2 * axis + (n[axis] < 0);
        const double inverse = 1 / m[axis];
        return table_[(face * kBins + bin(n[(axis + 1) % 3] * inverse)) * kBins + bin(n[(axis + 2) % 3] * inverse)];
    }

private:
    static int bin(double t) { return std::clamp(int(std::floor((t + 1) / 2 * kBins)), 0, kBins - 1); }

    /// The directions faced by every ray through the square (i, j) of @a face, and by rays
    /// within 1e-6 of it: the dot product is linear over the square, least at a corner.
    static std::uint32_t facing_all(int face, int i, int j) {
        const int axis = face / 2;
        const double sign = face % 2 ? -1 : 1;
        std::uint32_t facing = ~0u;
        for (const int di : {0, 1}) {
            for (const int dj : {0, 1}) {
                Vec3d corner{};
                corner[std::size_t(axis)] = sign;
                corner[std::size_t((axis + 1) % 3)] = -1 + 2.0 * (i + di) / kBins;
                corner[std::size_t((axis + 2) % 3)] = -1 + 2.0 * (j + dj) / kBins;
                const double length = std::sqrt(dot(corner, corner));
                std::uint32_t faced = 0;
                for (std::size_t k = 0; k < kDirections.size(); ++k) {
                    if (dot(kDirections[k], corner) > 1e-5 * length) faced |= 1u << k;
                }
                facing &= faced;
            }
        }
        return facing;
    }

    std::array<std::uint32_t, 6 * kBins * kBins> table_;
};

const FacingTable kFacingTable;

/// The directions of kDirections that triangle @a t certainly faces (its normal's dot product
/// with them is positive); none for a degenerate one.
std::uint32_t facing_directions(const detail::Triangle3& t) {
    const Vec3d e1 = sub(t[1], t[0]), e2 = sub(t[2], t[0]);
    return kFacingTable.facing(cross(e1, e2), dot(e1, e1) * dot(e2, e2));
}

/// Leaves the elements it makes default-initialized (a float or an index is not zeroed): the
/// decimator's arrays, about 650 MB for the bunny CT's 3 million triangles, are first written
/// by all threads, not zeroed by one when made.
template <class T>
struct Unzeroed : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = Unzeroed<U>;
    };
    Unzeroed() = default;
    template <class U>
    Unzeroed(const Unzeroed<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept(noexcept(U())) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};
template <class T>
using Array = std::vector<T, Unzeroed<T>>;

/// @a count elements made by @a make(i), in parallel.
template <class T, class Make>
Array<T> parallel_array(std::size_t count, Make&& make) {
    Array<T> array(count);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, std::size_t(1) << 16), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) array[i] = make(i);
    });
    return array;
}

/// Boxes with payloads (what a query needs of each, and a Summary) in a uniform grid, each in
/// the cell of its low corner (one larger than a cell: in every cell it meets), for finding the
/// boxes that meet a box, or what all those near a box have in common. Built at once and
/// read-only after.
template <class Payload>
class BoxGrid {
public:
    /// The boxes box_of(i) with payloads payload_of(i), i < @a count, but the empty ones
    /// (lo > hi), in cells of kCellEdges mean extents, made at least the largest extent of 99% of
    /// the boxes, and coarser where the boxes are spread thin (at most about eight cells per box).
    /// @a domain: the box the cells cover, when given (a box out of it is kept in the cells at
    /// its rim, and queries clamp the same way); else the boxes' box.
    template <class BoxOf, class PayloadOf>
    void build(std::size_t count, BoxOf&& box_of, PayloadOf&& payload_of, const Box* domain = nullptr) {
        struct Bounds {
            Box box = empty_box();
            std::size_t boxes = 0;  ///< not empty
        };
        const Bounds bounds = domain ? Bounds{*domain, count} : tbb::parallel_reduce(
            tbb::blocked_range<std::size_t>(0, count, 16384), Bounds{},
            [&](const auto& range, Bounds bounds) {
                for (std::size_t i = range.begin(); i != range.end(); ++i) {
                    const Box b = box_of(i);
                    if (!holds_nothing(b)) grow(bounds.box, b.lo), grow(bounds.box, b.hi), ++bounds.boxes;
                }
                return bounds;
            },
            [](Bounds a, const Bounds& b) { return grow(a.box, b.box.lo), grow(a.box, b.box.hi), a.boxes += b.boxes, a; });
        // (the extents of a regular sample: the cell size sets only the speed of the queries)
        constexpr std::size_t kExtentSamples = 65536;
        std::vector<float> extents;
        for (std::size_t i = 0; i < count; i += std::max<std::size_t>(1, count / kExtentSamples)) {
            const Box& b = box_of(i);
            if (!holds_nothing(b)) extents.push_back(std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]}));
        }
        double cell = extents.empty() ? 0 : kCellEdges * std::accumulate(extents.begin(), extents.end(), 0.0) / double(extents.size());
        if (!extents.empty()) {
            const auto most = extents.begin() + std::ptrdiff_t(std::size_t(0.99 * double(extents.size() - 1)));
            std::nth_element(extents.begin(), most, extents.end());
            cell = std::max(cell, double(*most));
        }
        cell_ = cell > 0 ? cell : 1;
        const bool none = bounds.boxes == 0;
        for (;;) {
            std::uint64_t cells = 1;
            for (int k = 0; k < 3; ++k) {
                origin_[k] = none ? 0 : bounds.box.lo[k];
                dims_[k] = none ? 1 : std::int64_t(std::floor((double(bounds.box.hi[k]) - origin_[k]) / cell_)) + 1;
                cells *= std::uint64_t(dims_[k]);
            }
            if (cells <= kCellsPerBox * bounds.boxes + 64) break;
            cell_ *= 1.25;
        }
        const std::size_t cells = std::size_t(dims_[0] * dims_[1] * dims_[2]);
        // A counting sort by cell: start_[c] counts up to the end of cell c, then down to its
        // start as its boxes are put in (from the last), so a cell keeps them in order.
        start_.assign(cells + 1, 0);
        // The cell of each box of a cell or less (found once, in parallel); kLarge for larger
        // ones, kNone for empty ones.
        constexpr std::uint32_t kLarge = kNone - 1;
        cell_of_.resize(count);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 8192), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                const Box& b = box_of(i);
                cell_of_[i] = holds_nothing(b) ? kNone : small(b) ? std::uint32_t(index(cell_coordinates(b.lo))) : kLarge;
            }
        });
        for (std::size_t i = 0; i < count; ++i) {
            if (cell_of_[i] < kLarge) ++start_[cell_of_[i]];
            else if (cell_of_[i] == kLarge) for_cells(box_of(i), [&](std::size_t c) { ++start_[c]; });
        }
        for (std::size_t c = 1; c <= cells; ++c) start_[c] += start_[c - 1];
        entries_.resize(start_[cells]);
        for (std::size_t i = count; i-- > 0;) {
            if (cell_of_[i] == kNone) continue;
            const Box& b = box_of(i);
            const auto put = [&](std::size_t c) {
                const std::uint32_t at = --start_[c];
                entries_[at] = {b, payload_of(i)};
            };
            if (cell_of_[i] != kLarge) put(cell_of_[i]);
            else for_cells(b, put);
        }
        // Each cell's summary at its first entry.
        summaries_.resize(start_[cells]);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 65536), [&](const auto& range) {
            for (std::size_t c = range.begin(); c != range.end(); ++c) {
                if (start_[c] == start_[c + 1]) continue;
                Summary common;
                for (std::uint32_t i = start_[c]; i < start_[c + 1]; ++i) common.add(entries_[i].payload.summary);
                summaries_[start_[c]] = common;
            }
        });
    }

    bool empty() const { return start_.empty(); }  ///< never built

    /// What the payloads of the boxes that meet @a box have in common (their summaries), with
    /// more (those of the cells visit() passes over).
    Summary summary(const Box& box) const {
        assert(summaries_.size() == entries_.size());
        Summary common;
        for_query_rows(box, [&](std::size_t first, std::size_t last) {
            for (std::size_t c = first; c <= last; ++c) {
                if (start_[c] != start_[c + 1]) common.add(summaries_[start_[c]]);
            }
            return true;
        });
        return common;
    }

    /// Calls visit(payload, box) for each entry whose box meets @a box (one larger than a cell may
    /// come more than once); stops when visit returns false. Returns whether it went through.
    template <class Visit>
    bool visit(const Box& box, Visit&& visit) const {
        return for_query_rows(box, [&](std::size_t first, std::size_t last) {
            for (std::uint32_t i = start_[first]; i < start_[last + 1]; ++i) {
                if (detail::boxes_overlap(entries_[i].box, box) && !visit(entries_[i].payload, entries_[i].box)) return false;
            }
            return true;
        });
    }

private:
    /// Calls rows(first, last) for each row of cells [first, last] that may hold a box meeting
    /// @a box, until it returns false; returns whether it went through. A box of a cell or less
    /// that meets @a box has its low corner in [box.lo - cell, box.hi], so in the cells from the
    /// one before box.lo's; a larger one is in the cells of a point they share.
    template <class Rows>
    bool for_query_rows(const Box& box, Rows&& rows) const {
        std::array<std::int64_t, 3> from = cell_coordinates(box.lo);
        for (std::int64_t& c : from) c = std::max<std::int64_t>(c - 1, 0);
        const std::array<std::int64_t, 3> to = cell_coordinates(box.hi);
        for (std::int64_t z = from[2]; z <= to[2]; ++z) {
            for (std::int64_t y = from[1]; y <= to[1]; ++y) {
                const std::size_t row = index({0, y, z});
                if (!rows(row + std::size_t(from[0]), row + std::size_t(to[0]))) return false;
            }
        }
        return true;
    }

    /// Calls call(cell) for each cell a box larger than a cell meets (a smaller box is kept in
    /// the cell of its low corner alone).
    template <class Call>
    void for_cells(const Box& box, Call&& call) const {
        const std::array<std::int64_t, 3> from = cell_coordinates(box.lo);
        const std::array<std::int64_t, 3> to = cell_coordinates(box.hi);
        for (std::int64_t z = from[2]; z <= to[2]; ++z) {
            for (std::int64_t y = from[1]; y <= to[1]; ++y) {
                for (std::int64_t x = from[0]; x <= to[0]; ++x) call(index({x, y, z}));
            }
        }
    }

    bool small(const Box& box) const {
        bool small = true;
        for (int k = 0; k < 3; ++k) small &= double(box.hi[k]) - box.lo[k] <= cell_;
        return small;
    }

    std::array<std::int64_t, 3> cell_coordinates(const std::array<float, 3>& p) const {
        std::array<std::int64_t, 3> c{};
        for (int k = 0; k < 3; ++k) {
            const double x = std::floor((double(p[k]) - origin_[k]) / cell_);
            c[k] = x < 0 ? 0 : x >= double(dims_[k]) ? dims_[k] - 1 : std::int64_t(x);
        }
        return c;
    }
    std::size_t index(const std::array<std::int64_t, 3>& c) const { return std::size_t(c[0] + dims_[0] * (c[1] + dims_[1] * c[2])); }

    double cell_ = 1;
    std::array<double, 3> origin_{};
    std::array<std::int64_t, 3> dims_{1, 1, 1};
    std::vector<std::uint32_t> start_;  ///< entries of cell c: [start_[c], start_[c + 1])
    struct Entry {
        Box box;
        Payload payload;
    };
    std::vector<Entry> entries_;      ///< by cell (a box beside its payload: one line to write when built)
    std::vector<Summary> summaries_;  ///< each cell's at its first entry
    std::vector<std::uint32_t> cell_of_;  ///< (build()'s, kept for its memory)
};

/// Boxes in columns, to find at once which of them meet a box (without a branch per box).
class BoxColumns {
public:
    void assign(const std::vector<Box>& boxes) {
        for (int k = 0; k < 3; ++k) {
            lo_[k].resize(boxes.size()), hi_[k].resize(boxes.size());
            for (std::size_t i = 0; i < boxes.size(); ++i) lo_[k][i] = boxes[i].lo[k], hi_[k][i] = boxes[i].hi[k];
        }
    }

    /// Calls call(i) for each box i that meets @a box, in order, until it returns false;
    /// returns whether it went through.
    template <class Call>
    bool for_meeting(const Box& box, Call&& call) const {
        const std::size_t size = lo_[0].size();
        for (std::size_t base = 0; base < size; base += 64) {
            const std::size_t count = std::min<std::size_t>(64, size - base);
            std::uint64_t meeting = 0;
            for (std::size_t i = 0; i < count; ++i) {
                const std::size_t j = base + i;
                const bool meets = (lo_[0][j] <= box.hi[0]) & (box.lo[0] <= hi_[0][j]) & (lo_[1][j] <= box.hi[1]) &
                                   (box.lo[1] <= hi_[1][j]) & (lo_[2][j] <= box.hi[2]) & (box.lo[2] <= hi_[2][j]);
                meeting |= std::uint64_t(meets) << i;
            }
            for (; meeting != 0; meeting &= meeting - 1) {
                if (!call(base + std::size_t(__builtin_ctzll(meeting)))) return false;
            }
        }
        return true;
    }

private:
    std::array<std::vector<float>, 3> lo_, hi_;
};

/// What the triangle grids hold of a triangle besides its box.
struct GridTriangle {
    std::uint32_t triangle;
    Summary summary;  ///< the directions it faces, its component
};

/// An edge a round considers, at the corner opposite it where it runs from its lower vertex
/// (the one kept) to its higher one.
struct Candidate {
    double cost;
    std::uint32_t corner;
    bool operator<(const Candidate& o) const { return cost != o.cost ? cost < o.cost : corner < o.corner; }
};
/// Sorts @a candidates, given in order of their corners, by cost (so in Candidate's order): a
/// stable least-significant-digit radix sort on the bits of the costs (non-negative doubles,
/// whose bits order as they do), 11 at a time, each pass over fixed chunks in parallel (the same
/// for any thread count); a pass is skipped where all share the digit.
void sort_by_cost(std::vector<Candidate>& candidates, std::vector<Candidate>& buffer) {
    constexpr int kDigitBits = 11;
    constexpr std::size_t kBuckets = std::size_t(1) << kDigitBits, kChunks = 16;
    const std::size_t size = candidates.size(), chunk = (size + kChunks - 1) / kChunks;
    buffer.resize(size);
    std::vector<std::array<std::uint32_t, kBuckets>> counts(kChunks);
    const auto key = [](const Candidate& c) {
        std::uint64_t bits;
        std::memcpy(&bits, &c.cost, sizeof bits);
        return bits;
    };
    for (int shift = 0; shift < 64; shift += kDigitBits) {
        const auto digit = [&](const Candidate& c) { return std::size_t(key(c) >> shift) & (kBuckets - 1); };
        tbb::parallel_for(std::size_t(0), kChunks, [&](std::size_t k) {
            counts[k].fill(0);
            for (std::size_t i = k * chunk; i < std::min(size, (k + 1) * chunk); ++i) ++counts[k][digit(candidates[i])];
        });
        std::size_t offset = 0;
        bool one_digit = false;
        for (std::size_t b = 0; b < kBuckets; ++b) {
            std::size_t in_bucket = 0;
            for (std::size_t k = 0; k < kChunks; ++k) {
                const std::uint32_t n = counts[k][b];
                counts[k][b] = std::uint32_t(offset + in_bucket), in_bucket += n;
            }
            one_digit |= in_bucket == size;
            offset += in_bucket;
        }
        if (one_digit) continue;
        tbb::parallel_for(std::size_t(0), kChunks, [&](std::size_t k) {
            for (std::size_t i = k * chunk; i < std::min(size, (k + 1) * chunk); ++i) buffer[counts[k][digit(candidates[i])]++] = candidates[i];
        });
        candidates.swap(buffer);
    }
}

constexpr Candidate kAboveAll{std::numeric_limits<double>::infinity(), kNone};  ///< (as a pivot: keeps every candidate)

enum class Verdict : std::uint8_t { unchecked, passed, topology, geometry, intersection };

/// A collapse a round may make.
struct Plan {
    std::uint32_t corner = kNone;
    /// the corners round its ends, as the choice walked them: around[0] at the kept end, then
    /// around[1] at the other, from ring_begin in the round's ring corners
    std::uint32_t ring_begin = 0;
    std::array<std::uint32_t, 2> around{};
    Box star = empty_box();  ///< the box of the new star (once checked for crossings)
    Verdict verdict = Verdict::unchecked;
    std::vector<std::uint32_t> crossed;  ///< earlier passed plans of the round whose new stars cross this one's
    double volume_change = 0;            ///< (once passed) six times the change of the enclosed volume
    Box region = empty_box();            ///< (once passed) the box of the old and the new star
    Summary fan;                         ///< (once passed) the directions all its new triangles face, its component
    /// (once passed) the directions faced by its new triangles and all those meeting its region
    /// at the start of the round (none: its crossings were tested), its component
    Summary apart{0, kNone};
};

/// What the plan grid holds of a plan besides the box of its new star.
struct GridPlan {
    std::uint32_t plan;
    Summary summary;  ///< the plan's fan
};

/// A ring walk of choose_apart(): the corners round both ends of the edge opposite corner.
struct Walk {
    std::uint32_t corner;
    std::array<std::uint32_t, 2> at;  ///< where each walk is
    std::array<std::vector<std::uint32_t>, 2> around;
    /// where the walk round end 0 (the kept vertex) or 1 begins and ends: at the edge's own triangle
    std::uint32_t first(int end) const { return end == 0 ? next(corner) : prev(corner); }
};

/// Per-thread scratch of the checks.
struct Scratch {
    std::vector<std::uint8_t> mark;  ///< stamp per vertex (the choice's; a byte, so they keep to the nearer caches)
    std::uint8_t stamp = 0;
    std::vector<std::uint32_t> star;  ///< the triangles of the new star
    std::vector<Ids> ids;             ///< their corners' vertices after the collapse
    std::vector<detail::Triangle3> corners;
    std::vector<detail::PreparedTriangle> prepared;  ///< the corners with their planes (for the intersection tests)
    BoxColumns box_columns;                          ///< the boxes (for the intersection tests)
    std::vector<Box> boxes;
    std::vector<std::array<Vec3d, 2>> spokes;  ///< per star triangle, from the kept vertex to its other corners
    std::vector<Walk> walks;  ///< choose_apart()'s
    std::array<std::vector<std::uint32_t>, 2> neighbours;  ///< the neighbours of a plan's ends (link condition)
};

/// The points between two planes across an axis, as far apart as the points added need (each
/// widened by the rounding of its distance along the axis, so a point added is certainly within).
struct Slab {
    Vec3d axis{}, origin{};
    double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
    void add(const Vec3d& p) {
        const detail::SignedDistance d = detail::along(axis, origin, p);
        lo = std::min(lo, d.value - d.error), hi = std::max(hi, d.value + d.error);
    }
    /// Whether the points of @a t certainly all lie beyond one of the planes (then the triangle
    /// misses the slab).
    bool misses(const FloatTriangle& t) const {
        int below = 0, above = 0;
        for (const auto& q : t) {
            const detail::SignedDistance d = detail::along(axis, origin, to_double(q));
            below += d.value + d.error < lo, above += d.value - d.error > hi;
        }
        return below == 3 || above == 3;
    }
};

class Decimator {
public:
    Decimator(const Mesh& mesh, const DecimateOptions& options)
        : positions_(parallel_array<std::array<float, 3>>(mesh.vertices.size(), [&](std::size_t v) { return mesh.vertices[v]; })),
          triangles_(parallel_array<Ids>(mesh.triangles.size(), [&](std::size_t t) { return mesh.triangles[t]; })),
          alive_(parallel_array<char>(mesh.triangles.size(), [](std::size_t) { return 1; })),
          opposite_(3 * mesh.triangles.size()),  // (link_corners() writes each, or fails)
          vertex_corner_(parallel_array<std::uint32_t>(mesh.vertices.size(), [](std::size_t) { return kNone; })),
          quadrics_(parallel_array<Quadric>(mesh.vertices.size(), [](std::size_t) { return Quadric{}; })),
          cost_(3 * mesh.triangles.size()), error_(3 * mesh.triangles.size()), position_(3 * mesh.triangles.size()),  // (refresh() writes them)
          rejected_(parallel_array<char>(3 * mesh.triangles.size(), [](std::size_t) { return 0; })),
          boxes_(mesh.triangles.size()),  // (refresh() writes each)
          summaries_(parallel_array<Summary>(mesh.triangles.size(), [](std::size_t) { return Summary{}; })),
          moved_(parallel_array<char>(mesh.triangles.size(), [](std::size_t) { return 0; })), alive_count_(mesh.triangles.size()),
          target_(options.target_triangles != 0 ? options.target_triangles
                                                : std::size_t(std::ceil(options.keep_fraction * double(mesh.triangles.size())))),
          max_error_squared_(options.max_error * options.max_error), closed_manifold_(link_corners()) {}

    /// Whether every edge has exactly two triangles, running either way, and every vertex one
    /// fan: the mesh is closed, manifold and oriented (what the decimation needs), found on the
    /// way to the corner table. When not, detail::analyze_topology() says what is wrong.
    bool closed_manifold() const { return closed_manifold_; }

    Mesh run(DecimateReport& report) {
        gather_quadrics();
        measure_components();
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(triangles_.size()), 4096), [&](const auto& range) {
            for (std::uint32_t t = range.begin(); t != range.end(); ++t) refresh(t);
        });
        tbb::enumerable_thread_specific<Scratch> scratch;
        std::vector<Candidate> candidates;
        std::vector<Plan> plans;
        Scratch own;
        own.mark.assign(positions_.size(), 0);
        while (alive_count_ > target_) {
            tbb::parallel_sort(dirty_.begin(), dirty_.end());  // (in memory order, as the checks below)
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, dirty_.size(), 1024), [&](const auto& range) {
                for (std::size_t i = range.begin(); i != range.end(); ++i) {
                    if (i + 8 < range.end()) {
                        const Ids& ahead = triangles_[dirty_[i + 8] / 3];
                        for (const std::uint32_t v : ahead) __builtin_prefetch(&quadrics_[v]), __builtin_prefetch(&quadrics_[v].d2), __builtin_prefetch(&positions_[v]);
                    }
                    refresh(dirty_[i] / 3, dirty_[i]);
                }
            });
            for (const std::uint32_t c : dirty_) {
                const std::uint32_t t = c / 3;
                if (!moved_[t]) moved_[t] = 1, moved_list_.push_back(t);
            }
            dirty_.clear();
            // The cheapest, about as many as the collapses still wanted (and never very few); with
            // under a quarter of the triangles to go, four times as many: about a third of them
            // are chosen and pass, so a round then makes about all the collapses wanted, where
            // as many would leave a tail of rounds that each pass over the whole mesh for a few
            // collapses (bunny: 16 rounds -> 14, 0.1 s of 3.8; the mean distance to the input +1%).
            const std::size_t collapses = (alive_count_ - target_ + 1) / 2;
            const std::size_t wanted = alive_count_ - target_ < alive_count_ / 4 ? 4 * collapses : collapses;
            const std::size_t take = std::max({kMinRound, wanted, alive_count_ / kMinRoundDivisor});
            if (gather_cheap(candidates, take) == 0) break;
            // The grids the checks read are built beside the sorting and the choice (mostly
            // sequential), which read neither them nor what building them writes.
            tbb::task_group grids;
            grids.run([&] { build_triangle_grids(); });
            keep_cheapest(candidates, take);
            choose_apart(candidates, plans, ring_corners_, own);
            grids.wait();
            // Checked in the order of their triangles, which keeps neighbours together in memory
            // (the checks are independent of each other; the cost order scatters them).
            std::vector<std::uint32_t> in_place(plans.size());
            for (std::uint32_t i = 0; i < plans.size(); ++i) in_place[i] = i;
            tbb::parallel_sort(in_place.begin(), in_place.end(), [&](std::uint32_t i, std::uint32_t j) { return plans[i].corner < plans[j].corner; });
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, plans.size(), 256), [&](const auto& range) {
                Scratch& s = scratch.local();
                for (std::size_t n = range.begin(); n != range.end(); ++n) {
                    // (in cost order the plans lie anywhere: each asked for 24 ahead, its star's
                    // triangles 16 ahead, their corners' points 8 ahead)
                    if (n + 24 < range.end()) __builtin_prefetch(&plans[in_place[n + 24]], 1);
                    if (n + 16 < range.end()) for_star(plans[in_place[n + 16]], [&](const Ids& t) { __builtin_prefetch(&t); });
                    if (n + 8 < range.end()) {
                        for_star(plans[in_place[n + 8]], [&](const Ids& t) {
                            for (const std::uint32_t v : t) __builtin_prefetch(&positions_[v]);
                        });
                    }
                    plans[in_place[n]].verdict = check(plans[in_place[n]], s);
                }
            });
            find_crossings(plans, in_place, scratch);
            apply_round(plans, report);
        }
        return compact();
    }

private:
    // ---- the corner table: corner c is vertex c % 3 of triangle c / 3 ----

    std::uint32_t vertex(std::uint32_t c) const { return triangles_[c / 3][c % 3]; }

    /// Each corner's opposite: the corner of the other triangle on the edge opposite it (that
    /// edge runs vertex(next c) -> vertex(prev c), and the other way in the other triangle).
    /// Returns closed_manifold().
    bool link_corners() {
        const std::size_t n = positions_.size();
        const auto corners = std::uint32_t(3 * triangles_.size());
        std::vector<std::uint32_t> start(n + 1, 0);
        for (std::uint32_t c = 0; c < corners; ++c) ++start[vertex(c) + 1];
        for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
        std::vector<std::uint32_t> at(start[n]);  // the corners at each vertex
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::uint32_t c = 0; c < corners; ++c) at[fill[vertex(c)]++] = c;
        // Round each vertex v: the edge from v to x, after its corner c, pairs with the edge from x
        // to v, before its corner d (both at v): the corners opposite them are prev(c) and next(d).
        std::atomic<bool> paired{true};
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
            for (std::size_t v = range.begin(); v != range.end(); ++v) {
                for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) {
                    const std::uint32_t c = at[i], x = vertex(next(c));
                    int found = 0;
                    for (std::uint32_t j = start[v]; j < start[v + 1]; ++j) {
                        if (vertex(prev(at[j])) == x) opposite_[prev(c)] = next(at[j]), ++found;
                    }
                    if (found != 1) paired = false;
                }
            }
        });
        for (std::uint32_t c = 0; c < corners; ++c) vertex_corner_[vertex(c)] = c;
        if (!paired) return false;
        // Each edge paired once (so opposite_ is an involution and every walk round a vertex
        // closes): a vertex is manifold when its walk meets all its corners.
        std::atomic<bool> fans{true};
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
            for (std::size_t v = range.begin(); v != range.end(); ++v) {
                if (start[v] == start[v + 1]) continue;
                std::uint32_t count = 0;
                around(std::uint32_t(v), [&](std::uint32_t) { ++count; });
                if (count != start[v + 1] - start[v]) fans = false;
            }
        });
        return fans;
    }

    /// The next corner at the same vertex (across the edge to vertex(next c)).
    std::uint32_t swing(std::uint32_t c) const { return prev(opposite_[prev(c)]); }

    /// Calls visit(corner) for each corner at @a v.
    template <class Visit>
    void around(std::uint32_t v, Visit&& visit) const {
        const std::uint32_t first = vertex_corner_[v];
        std::uint32_t c = first;
        do {
            visit(c);
            c = swing(c);
        } while (c != first);
    }

    // ---- quadrics, costs, boxes ----

    Vec3d point(std::uint32_t v) const { return to_double(positions_[v]); }
    Vec3d normal(const Ids& t) const { return cross(sub(point(t[1]), point(t[0])), sub(point(t[2]), point(t[0]))); }

    /// Each vertex's quadric: the planes of its triangles, summed around it.
    void gather_quadrics() {
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(positions_.size()), 4096), [&](const auto& range) {
            for (std::uint32_t v = range.begin(); v != range.end(); ++v) {
                if (vertex_corner_[v] == kNone) continue;
                around(v, [&](std::uint32_t c) {
                    const Ids& t = triangles_[c / 3];
                    const Vec3d n = normal(t);
                    const double length = std::sqrt(dot(n, n));
                    if (length == 0) return;
                    quadrics_[v] = quadrics_[v] + Quadric::plane({n[0] / length, n[1] / length, n[2] / length}, point(t[0]));
                });
            }
        });
    }

    /// Where the collapse of (a, b), whose quadrics add up to @a q, puts the vertex, rounded to
    /// floats: the quadric's minimizer when it is defined and near the edge, else the best of the
    /// ends and the midpoint.
    std::array<float, 3> placement(const Quadric& q, std::uint32_t a, std::uint32_t b) const {
        const Vec3d pa = point(a), pb = point(b);
        const Vec3d mid{(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2};
        if (const auto best = q.minimizer()) {
            const Vec3d offset = sub(*best, mid), edge = sub(pb, pa);
            if (dot(offset, offset) <= dot(edge, edge)) return to_float(*best);
        }
        Vec3d chosen = mid;
        for (const Vec3d& p : {pa, pb}) {
            if (q.error(p) < q.error(chosen)) chosen = p;
        }
        return to_float(chosen);
    }

    /// Triangle @a t's box and the costs of its edges (each at the corner where it runs from the
    /// lower vertex) but the one opposite corner @a unchanged (its ends have neither moved nor
    /// merged: its cached cost holds); none of them refused any more.
    void refresh(std::uint32_t t, std::uint32_t unchanged = kNone) {
        boxes_[t] = empty_box();
        summaries_[t].facing = facing_directions(to_double(FloatTriangle{positions_[triangles_[t][0]], positions_[triangles_[t][1]], positions_[triangles_[t][2]]}));
        for (std::uint32_t c = 3 * t; c < 3 * t + 3; ++c) {
            grow(boxes_[t], positions_[vertex(c)]);
            rejected_[c] = 0;
            const std::uint32_t a = vertex(next(c)), b = vertex(prev(c));
            if (a > b) cost_[c] = kNever;
            if (a > b || c == unchanged) continue;
            const Quadric q = quadrics_[a] + quadrics_[b];
            position_[c] = placement(q, a, b);
            const double error = q.error(to_double(position_[c]));
            const Vec3d edge = sub(point(a), point(b));
            error_[c] = error;
            cost_[c] = error <= max_error_squared_ ? error + kLengthWeight * dot(edge, edge) : kNever;
        }
    }

    /// Whether the edge opposite corner @a c (of an alive triangle) may collapse now, seen from
    /// the corner where it runs from its lower vertex.
    bool collapsible(std::uint32_t c) const { return cost_[c] != kNever && !rejected_[c]; }

    /// The edges that may collapse, at least the @a take cheapest of them (all, when fewer), in
    /// the order of their corners; returns how many may collapse. Only those below a pivot are
    /// kept as they are gathered: the same as all of them once sorted and cut, should at least
    /// @a take fall below it (else all are gathered again).
    std::size_t gather_cheap(std::vector<Candidate>& candidates, std::size_t take) {
        const Candidate pivot = pivot_above(take);
        const std::size_t count = gather_below(pivot, candidates);
        if (candidates.size() < std::min(count, take) && pivot < kAboveAll) gather_below(kAboveAll, candidates);
        return count;
    }

    /// Of gather_cheap()'s @a candidates, the @a take cheapest in order of cost (a total order:
    /// ties go by corner), whatever the thread count.
    void keep_cheapest(std::vector<Candidate>& candidates, std::size_t take) {
        sort_by_cost(candidates, sort_buffer_);
        if (candidates.size() > take) candidates.resize(take);
    }

    /// A candidate just above the @a take-th cheapest (most likely), from a regular sample of the
    /// corners: four standard deviations of the sample's count and 3% high (the share itself is
    /// estimated from the sample); none (above all) when they would be half or more.
    Candidate pivot_above(std::size_t take) const {
        constexpr std::size_t kSamples = 16384;
        const std::size_t corners = 3 * triangles_.size();
        std::vector<Candidate> sample;
        for (std::size_t i = 0; i < kSamples; ++i) {
            const auto c = std::uint32_t(i * corners / kSamples);
            if (alive_[c / 3] && collapsible(c)) sample.push_back({cost_[c], c});
        }
        const auto n = double(sample.size());
        const double share = double(take) / (n * double(corners) / double(kSamples));
        if (sample.empty() || share >= 0.5) return kAboveAll;
        const auto rank = std::size_t(share * n * 1.03 + 4 * std::sqrt(n * share * (1 - share))) + 1;
        if (rank >= sample.size()) return kAboveAll;
        std::nth_element(sample.begin(), sample.begin() + std::ptrdiff_t(rank), sample.end());
        return sample[rank];
    }

    /// The edges that may collapse whose candidates are below @a pivot, in the order of their
    /// corners (whatever the thread count: each block of triangles is gathered on its own, then
    /// the blocks are put end to end); returns how many may collapse in all.
    std::size_t gather_below(const Candidate& pivot, std::vector<Candidate>& candidates) {
        constexpr std::uint32_t kBlock = 16384;
        const auto triangles = std::uint32_t(triangles_.size());
        block_candidates_.resize((triangles + kBlock - 1) / kBlock);
        std::vector<std::size_t> counts(block_candidates_.size());
        tbb::parallel_for(std::size_t(0), block_candidates_.size(), [&](std::size_t block) {
            std::vector<Candidate>& found = block_candidates_[block];
            found.clear();
            std::size_t count = 0;
            for (auto t = std::uint32_t(block * kBlock); t < std::min(triangles, std::uint32_t((block + 1) * kBlock)); ++t) {
                if (!alive_[t]) continue;
                for (std::uint32_t c = 3 * t; c < 3 * t + 3; ++c) {
                    if (!collapsible(c)) continue;
                    ++count;
                    if (const Candidate candidate{cost_[c], c}; candidate < pivot) found.push_back(candidate);
                }
            }
            counts[block] = count;
        });
        std::vector<std::size_t> offsets(block_candidates_.size() + 1, 0);
        for (std::size_t b = 0; b < block_candidates_.size(); ++b) offsets[b + 1] = offsets[b] + block_candidates_[b].size();
        candidates.resize(offsets.back());
        tbb::parallel_for(std::size_t(0), block_candidates_.size(), [&](std::size_t b) {
            std::copy(block_candidates_[b].begin(), block_candidates_[b].end(), candidates.begin() + std::ptrdiff_t(offsets[b]));
        });
        return std::accumulate(counts.begin(), counts.end(), std::size_t(0));
    }

    // ---- a round ----

    /// The candidates, in order of cost, whose ends lie in the star of no earlier one chosen.
    /// Then no collapse of the round changes the rings of another's ends or the triangles of its
    /// star (a triangle changes only if it has an end of the collapse, and a vertex's ring only
    /// if it is in the star), which is what the link condition and the geometry check read.
    /// Each plan's corners round its ends go to @a rings (the checks read them from there without
    /// walking the rings again, a chain of loads). The rings are walked a batch of candidates at a
    /// time, side by side (many chains of loads in flight, not one): the next ones whose ends no
    /// earlier choice has marked, then chosen in order as before (one may yet be marked by one
    /// chosen before it in the batch; its walk is then wasted).
    void choose_apart(const std::vector<Candidate>& candidates, std::vector<Plan>& plans, std::vector<std::uint32_t>& rings, Scratch& s) const {
        plans.clear(), rings.clear();
        if (++s.stamp == 0) std::fill(s.mark.begin(), s.mark.end(), 0), s.stamp = 1;
        const std::uint8_t stamp = s.stamp;
        const auto marked = [&](std::uint32_t corner) { return s.mark[vertex(next(corner))] == stamp || s.mark[vertex(prev(corner))] == stamp; };
        constexpr std::size_t kBatch = 32;
        s.walks.resize(kBatch);
        for (std::size_t n = 0; n < candidates.size();) {
            std::size_t size = 0;
            for (; n < candidates.size() && size < kBatch; ++n) {
                // (in cost order the candidates lie anywhere: their triangles and those triangles'
                // opposite corners asked for 16 ahead, then their ends' marks 8 ahead)
                if (n + 16 < candidates.size()) {
                    const std::uint32_t ahead = candidates[n + 16].corner;
                    __builtin_prefetch(&triangles_[ahead / 3]), __builtin_prefetch(&opposite_[ahead - ahead % 3]);
                }
                if (n + 8 < candidates.size()) {
                    const std::uint32_t ahead = candidates[n + 8].corner;
                    for (const std::uint32_t v : {vertex(next(ahead)), vertex(prev(ahead))}) __builtin_prefetch(&s.mark[v]);
                }
                if (!marked(candidates[n].corner)) s.walks[size++].corner = candidates[n].corner;
            }
            walk_rings(s.walks.data(), size);
            for (std::size_t k = 0; k < size; ++k) {
                const Walk& walk = s.walks[k];
                if (marked(walk.corner)) continue;
                Plan plan;
                plan.corner = walk.corner;
                plan.ring_begin = std::uint32_t(rings.size());
                for (int end = 0; end < 2; ++end) {
                    plan.around[end] = std::uint32_t(walk.around[end].size());
                    for (const std::uint32_t c : walk.around[end]) s.mark[vertex(next(c))] = stamp, rings.push_back(c);
                }
                plans.push_back(plan);
            }
        }
    }

    /// The corners round both ends of each of @a walks, from the edge's own triangle, all walked
    /// side by side.
    void walk_rings(Walk* walks, std::size_t size) const {
        std::size_t walking = 0;
        for (std::size_t k = 0; k < size; ++k) {
            Walk& walk = walks[k];
            for (int end = 0; end < 2; ++end) walk.around[end].clear(), walk.at[end] = walk.first(end);
            walking += 2;
        }
        while (walking > 0) {
            for (std::size_t k = 0; k < size; ++k) {
                Walk& walk = walks[k];
                for (int end = 0; end < 2; ++end) {
                    std::vector<std::uint32_t>& around = walk.around[end];
                    if (!around.empty() && walk.at[end] == walk.first(end)) continue;
                    around.push_back(walk.at[end]);
                    __builtin_prefetch(&triangles_[walk.at[end] / 3]);  // (its neighbour is marked once chosen)
                    walk.at[end] = swing(walk.at[end]);
                    walking -= walk.at[end] == walk.first(end);
                }
            }
        }
    }

    /// For each plan that passed its checks, the earlier ones that did too and whose new stars
    /// cross its own: no plan's ends are in another's star, so each check still holds but for
    /// the new triangles of two collapses of the round, which no check has met. Both new stars
    /// are as the checks built them from the mesh at the start of the round: no other collapse
    /// of the round changes them (their vertices are neither collapse's ends nor its ends'
    /// neighbours; two stars may share link vertices, which the exact tests allow for).
    /// @a in_place: the plans in the order to visit them (any order gives the same crossings).
    void find_crossings(std::vector<Plan>& plans, const std::vector<std::uint32_t>& in_place,
                        tbb::enumerable_thread_specific<Scratch>& scratch) {
        plan_grid_.build(
            plans.size(), [&](std::size_t i) { return plans[i].verdict == Verdict::passed ? plans[i].star : empty_box(); },
            [&](std::size_t i) { return GridPlan{std::uint32_t(i), plans[i].fan}; });
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, in_place.size(), 64), [&](const auto& range) {
            Scratch& s = scratch.local();
            for (std::size_t n = range.begin(); n != range.end(); ++n) {
                if (n + 8 < range.end()) __builtin_prefetch(&plans[in_place[n + 8]]);  // (in cost order: anywhere)
                const std::uint32_t i = in_place[n];
                Plan& p = plans[i];
                if (p.verdict != Verdict::passed) continue;
                p.crossed.clear();
                if (apart_from_all(p)) continue;
                bool star_ready = false;
                plan_grid_.visit(p.star, [&](const GridPlan& entry, const Box&) {
                    const std::uint32_t j = entry.plan;
                    if (j >= i) return true;
                    if (!star_ready) {
                        s.ids.clear(), s.corners.clear(), s.boxes.clear();
                        for_new_star(p, [&](std::uint32_t, const Ids& ids, const FloatTriangle& points, const Box& box) {
                            s.ids.push_back(ids), s.corners.push_back(to_double(points)), s.boxes.push_back(box);
                            return true;
                        });
                        prepare_star(s);
                        star_ready = true;
                    }
                    if (crosses_new_star(plans[j], p.star, s)) p.crossed.push_back(j);
                    return true;
                });
            }
        });
    }

    /// Applies the plans that passed their checks, in order of cost, while triangles are to go;
    /// a plan whose new star crosses that of one applied before waits for the next round. The
    /// cost order decides which apply; they are then applied in the order of their triangles
    /// (neighbours together in memory), side by side: their stars share no triangle, so no
    /// collapse reads or writes what another writes but vertex_corner_ at a link vertex two
    /// stars share, which is set after, in that order.
    void apply_round(const std::vector<Plan>& plans, DecimateReport& report) {
        std::vector<char> applied(plans.size(), 0);
        std::vector<std::uint32_t> chosen;
        std::size_t alive = alive_count_;
        for (std::uint32_t i = 0; i < plans.size() && alive > target_; ++i) {
            const Plan& p = plans[i];
            if (p.verdict != Verdict::passed) {
                rejected_[p.corner] = 1;
                ++(p.verdict == Verdict::topology ? report.rejected_topology
                   : p.verdict == Verdict::geometry ? report.rejected_geometry
                                                    : report.rejected_intersection);
                continue;
            }
            if (std::any_of(p.crossed.begin(), p.crossed.end(), [&](std::uint32_t j) { return applied[j] != 0; })) continue;
            double& volume = volume_[p.fan.component];
            if (volume != 0 && (volume + p.volume_change) * volume <= 0) {  // the component would turn inside out
                rejected_[p.corner] = 1;
                ++report.rejected_geometry;
                continue;
            }
            volume += p.volume_change;
            applied[i] = 1;
            chosen.push_back(p.corner);
            alive -= 2;
        }
        tbb::parallel_sort(chosen.begin(), chosen.end());
        tbb::enumerable_thread_specific<std::vector<std::uint32_t>> dirty;
        tbb::enumerable_thread_specific<double> max_error(0.0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chosen.size(), 256), [&](const auto& range) {
            std::vector<std::uint32_t>& local = dirty.local();
            double& largest = max_error.local();
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                largest = std::max(largest, error_[chosen[i]]);
                if (i + 8 < range.end()) {  // (the ends' quadrics are read at random)
                    const std::uint32_t ahead = chosen[i + 8];
                    for (const std::uint32_t v : {vertex(next(ahead)), vertex(prev(ahead))}) __builtin_prefetch(&quadrics_[v], 1), __builtin_prefetch(&vertex_corner_[v], 1);
                }
                apply(chosen[i], local);
            }
        });
        for (const std::uint32_t corner : chosen) name_opposite_corners(corner);
        for (const double error : max_error) report.max_error = std::max(report.max_error, std::sqrt(error));
        report.collapses += chosen.size();
        alive_count_ -= 2 * chosen.size();
        for (const std::vector<std::uint32_t>& local : dirty) dirty_.insert(dirty_.end(), local.begin(), local.end());  // (sorted before use)
    }

    /// Whether @a p's new star certainly crosses no other of the round, whichever of them apply
    /// before it: the directions its check found faced in its region are also faced by the new
    /// stars of all passed plans near it, of its component (so the mesh as it is when p applies,
    /// the round's start but for those stars, meets intersection_free()'s condition). The plan
    /// grid's cells tell first what the stars in them have in common; failing that, the stars met.
    bool apart_from_all(const Plan& p) const {
        if (!p.apart.clears()) return false;
        Summary in_cells = p.apart;
        in_cells.add(plan_grid_.summary(p.region));
        if (in_cells.clears()) return true;
        Summary met = p.apart;
        plan_grid_.visit(p.region, [&](const GridPlan& q, const Box&) { return met.add(q.summary), met.clears(); });
        return met.clears();
    }

    /// Whether a triangle of the new star in @a s (whose box is @a star) crosses one of the new
    /// star of plan @a q (neither holds the other's kept vertex).
    bool crosses_new_star(const Plan& q, const Box& star, const Scratch& s) const {
        return !for_new_star(q, [&](std::uint32_t, const Ids& ids, const FloatTriangle& points, const Box& box) {
            if (!detail::boxes_overlap(star, box)) return true;
            const detail::PreparedTriangle corners(to_double(points));
            return s.box_columns.for_meeting(box, [&](std::size_t i) { return !detail::triangles_intersect(s.ids[i], s.prepared[i], ids, corners); });
        });
    }

    /// The alive triangles with their boxes, in cells of kCellEdges mean extents: those that
    /// moved since the settled grid was built in a grid of their own, rebuilt each round; the
    /// settled grid rebuilt only once a quarter of the triangles has moved.
    void build_triangle_grids() {
        const auto dead = [&](std::uint32_t t) { return alive_[t] == 0; };
        const bool all = settled_grid_.empty() || moved_list_.size() > alive_count_ / 4;
        if (all) {
            for (const std::uint32_t t : moved_list_) moved_[t] = 0;
            moved_list_.clear();
            if (alive_list_.empty()) alive_list_.resize(triangles_.size()), std::iota(alive_list_.begin(), alive_list_.end(), 0u);
            alive_list_.erase(std::remove_if(alive_list_.begin(), alive_list_.end(), dead), alive_list_.end());
        } else {
            moved_list_.erase(std::remove_if(moved_list_.begin(), moved_list_.end(), dead), moved_list_.end());
        }
        const std::vector<std::uint32_t>& ids = all ? alive_list_ : moved_list_;
        const auto box_of = [&](std::size_t i) { return boxes_[ids[i]]; };
        const auto payload_of = [&](std::size_t i) { return GridTriangle{ids[i], summaries_[ids[i]]}; };
        if (!all) {
            moved_grid_.build(ids.size(), box_of, payload_of);
            return;
        }
        // (the settled grid over the box of the first triangles: the collapses keep to it but by
        // a little, and the pass over all boxes for theirs is spared)
        if (holds_nothing(domain_)) {
            for (std::size_t i = 0; i < ids.size(); ++i) grow(domain_, box_of(i).lo), grow(domain_, box_of(i).hi);
        }
        settled_grid_.build(ids.size(), box_of, payload_of, &domain_);
        moved_grid_.build(0, [](std::size_t) { return empty_box(); }, [](std::size_t) { return GridTriangle{}; });
    }

    /// Calls visit(GridTriangle, box) for each alive triangle whose box meets @a box, until it returns
    /// false; returns whether it went through.
    template <class Visit>
    bool visit_triangles(const Box& box, Visit&& visit) const {
        if (moved_list_.empty()) return settled_grid_.visit(box, visit);  // (just rebuilt: none moved since)
        return settled_grid_.visit(box, [&](const GridTriangle& t, const Box& b) { return moved_[t.triangle] || visit(t, b); }) &&
               moved_grid_.visit(box, visit);
    }

    /// Calls visit(triangle) for each triangle round the ends of @a p (as the choice walked them).
    template <class Visit>
    void for_star(const Plan& p, Visit&& visit) const {
        const std::uint32_t* ring = ring_corners_.data() + p.ring_begin;
        for (std::uint32_t n = 0; n < p.around[0] + p.around[1]; ++n) visit(triangles_[ring[n] / 3]);
    }

    /// Calls visit(triangle, its vertices, their points, its box) for each triangle of @a p's
    /// new star (the triangles round its ends but the two on its edge, with b renamed a and a
    /// moved), from the corners the choice walked, until it returns false; returns whether it
    /// went through. The same while the round's collapses wait: the checks and the crossing
    /// tests see the same star.
    template <class Visit>
    bool for_new_star(const Plan& p, Visit&& visit) const {
        const std::uint32_t a = vertex(next(p.corner)), b = vertex(prev(p.corner));
        const std::array<float, 3>& position = position_[p.corner];
        const std::uint32_t t0 = p.corner / 3, t1 = opposite_[p.corner] / 3;
        const std::uint32_t* ring = ring_corners_.data() + p.ring_begin;
        for (std::uint32_t n = 0; n < p.around[0] + p.around[1]; ++n) {
            const std::uint32_t t = ring[n] / 3;
            if (t == t0 || t == t1) continue;
            Ids ids = triangles_[t];
            FloatTriangle points;
            Box box = empty_box();
            for (int k = 0; k < 3; ++k) {
                if (ids[k] == b) ids[k] = a;
                points[k] = ids[k] == a ? position : positions_[ids[k]];
                grow(box, points[k]);
            }
            if (!visit(t, ids, points, box)) return false;
        }
        return true;
    }

    /// Whether the edge of @a p meets the link condition (its ends' neighbours in common are only
    /// the two opposite corners; the kept vertex keeps three neighbours at least), and its new
    /// star in @a s (for_new_star(): its triangles, their corners as doubles, their boxes).
    bool linked_new_star(const Plan& p, Scratch& s) const {
        if (vertex(p.corner) == vertex(opposite_[p.corner])) return false;
        s.star.clear(), s.ids.clear(), s.corners.clear(), s.boxes.clear();
        for_new_star(p, [&](std::uint32_t t, const Ids& ids, const FloatTriangle& points, const Box& box) {
            s.star.push_back(t), s.ids.push_back(ids), s.corners.push_back(to_double(points)), s.boxes.push_back(box);
            return true;
        });
        const std::uint32_t* ring = ring_corners_.data() + p.ring_begin;
        for (const int end : {0, 1}) {
            const std::uint32_t* corners = end == 0 ? ring : ring + p.around[0];
            std::vector<std::uint32_t>& neighbours = s.neighbours[end];
            neighbours.clear();
            for (std::uint32_t n = 0; n < p.around[end]; ++n) neighbours.push_back(vertex(next(corners[n])));
            std::sort(neighbours.begin(), neighbours.end());
        }
        std::size_t common = 0;
        for (auto i = s.neighbours[0].begin(), j = s.neighbours[1].begin(); i != s.neighbours[0].end() && j != s.neighbours[1].end();) {
            if (*i == *j) ++common, ++i, ++j;
            else if (*i < *j) ++i;
            else ++j;
        }
        return common == 2 && p.around[0] + p.around[1] >= 4 + 3;
    }

    bool geometry_holds(const Scratch& s) const {
        for (std::size_t i = 0; i < s.star.size(); ++i) {
            const detail::Triangle3& c = s.corners[i];
            if (detail::collinear(c[0], c[1], c[2])) return false;
            const Vec3d before = normal(triangles_[s.star[i]]), after = cross(sub(c[1], c[0]), sub(c[2], c[0]));
            if (dot(before, after) < kMinTurnCosine * std::sqrt(dot(before, before) * dot(after, after))) return false;
        }
        return true;
    }

    /// Whether the new star (a closed fan around the kept vertex @a a) is certainly free of
    /// crossings among its triangles: seen along one direction, each turns the same way (exact
    /// orientations) and their angles at the kept vertex add up to one turn (the sum is a whole
    /// number of turns, so rounding cannot mislead), so the fan projects one-to-one onto a plane.
    bool star_is_a_graph(std::uint32_t a, Scratch& s) const {
        std::vector<std::array<Vec3d, 2>>& spokes = s.spokes;
        spokes.resize(s.star.size());
        Vec3d n{0, 0, 0};
        double reach = 0;
        for (std::size_t i = 0; i < s.star.size(); ++i) {
            const int k = s.ids[i][0] == a ? 0 : s.ids[i][1] == a ? 1 : 2;
            spokes[i] = {sub(s.corners[i][(k + 1) % 3], s.corners[i][k]), sub(s.corners[i][(k + 2) % 3], s.corners[i][k])};
            const Vec3d c = cross(spokes[i][0], spokes[i][1]);
            for (int j = 0; j < 3; ++j) n[j] += c[j];
            reach = std::max(reach, dot(spokes[i][0], spokes[i][0]));
        }
        const double length = std::sqrt(dot(n, n));
        if (!(length > 0)) return false;
        const Vec3d& p = s.corners[0][s.ids[0][0] == a ? 0 : s.ids[0][1] == a ? 1 : 2];
        const double scale = std::sqrt(reach) / length;
        const Vec3d q{p[0] + n[0] * scale, p[1] + n[1] * scale, p[2] + n[2] * scale};
        // A basis of the plane across n, for the angles.
        const Vec3d d{n[0] / length, n[1] / length, n[2] / length};
        const Vec3d helper = std::abs(d[0]) < 0.6 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
        Vec3d u = cross(d, helper);
        const double u_length = std::sqrt(dot(u, u));
        u = {u[0] / u_length, u[1] / u_length, u[2] / u_length};
        const Vec3d v = cross(d, u);
        int turn = 0;
        double angles = 0;
        for (std::size_t i = 0; i < s.star.size(); ++i) {
            const int k = s.ids[i][0] == a ? 0 : s.ids[i][1] == a ? 1 : 2;
            const int sign = detail::orient3d(s.corners[i][k], s.corners[i][(k + 1) % 3], s.corners[i][(k + 2) % 3], q);
            if (sign == 0 || (turn != 0 && sign != turn)) return false;
            turn = sign;
            const double x1 = dot(spokes[i][0], u), y1 = dot(spokes[i][0], v), x2 = dot(spokes[i][1], u), y2 = dot(spokes[i][1], v);
            angles += std::atan2(std::abs(x1 * y2 - x2 * y1), x1 * x2 + y1 * y2);
        }
        return angles < 3 * 3.14159265358979323846;
    }

    /// s.prepared and s.box_columns from s.corners and s.boxes.
    static void prepare_star(Scratch& s) {
        s.prepared.clear();
        for (const detail::Triangle3& t : s.corners) s.prepared.emplace_back(t);
        s.box_columns.assign(s.boxes);
    }

    /// The new triangles cross neither each other nor any triangle near them off the old star.
    ///
    /// Most collapses are settled without a test between triangles: the new star crosses
    /// nothing when some direction d is faced by all its triangles and by all those that meet a
    /// convex region R holding the old and the new star, and those all belong to one component
    /// (R: first the box of both stars, taken a grid cell at a time; then that box cut to the
    /// slab of slab_around(), which leaves out most of a thin wall's far side):
    /// - Along a line the winding number of a closed embedded surface changes by one at each
    ///   crossing, up or down as the triangle faces; one component's takes two values only. So a
    ///   segment along d within R (convex) crosses the surface at most once, and the
    ///   surface in R projects one-to-one onto a plane across d, the old star too; its rim L
    ///   projects to a simple loop and the old star onto the inside of it.
    /// - Each triangle of the new fan (from the new vertex to L) turns the same way seen along d,
    ///   so their angles at the new vertex add up to a turn times the winding number of L's
    ///   projection around it: one. The fan projects one-to-one onto the same inside of L.
    /// - Should the fan meet another triangle T at x off L, the segment along d from x to the
    ///   point of the old star over or under x would lie within R and cross the old surface
    ///   twice (T is part of it); at x on L, T met the old star there before, which the mesh
    ///   allowed only at a vertex or edge T shares with it, and so with the fan.
    /// (Two components, say a sphere within another facing the same way, would break the first
    /// point. The rounds begin free of crossings, so the surface is embedded.) The grids' cells
    /// tell first what the triangles in them have in common; failing that, the triangles met.
    bool intersection_free(Plan& p, Scratch& s) const {
        const std::uint32_t a = vertex(next(p.corner)), b = vertex(prev(p.corner));
        Box& around_star = p.star;
        for (const Box& box : s.boxes) grow(around_star, box.lo), grow(around_star, box.hi);
        Box& region = p.region;
        region = around_star;
        grow(region, positions_[a]), grow(region, positions_[b]);
        p.fan = {~0u, summaries_[p.corner / 3].component};
        for (const detail::Triangle3& t : s.corners) p.fan.facing &= facing_directions(t);
        const auto apart = [&](Summary near) {
            near.add(p.fan);
            if (!near.clears()) return false;
            p.apart = near;
            return true;
        };
        Summary in_cells = settled_grid_.summary(region);
        in_cells.add(moved_grid_.summary(region));
        if (apart(in_cells)) return true;
        const Slab slab = slab_around(p, s);
        // (the triangles met: the visit stops as soon as they cannot clear the collapse)
        Summary met;
        const auto may_clear = [&](Summary near) { return near.add(p.fan), near.clears(); };
        const auto add_met = [&](const GridTriangle& t, const Box&) {
            if (!slab.misses(points_of(triangles_[t.triangle]))) met.add(t.summary);
            return may_clear(met);
        };
        if (visit_triangles(region, add_met) && apart(met)) return true;
        prepare_star(s);
        if (!star_is_a_graph(a, s)) {
            for (std::size_t i = 0; i < s.star.size(); ++i) {
                for (std::size_t j = 0; j < i; ++j) {
                    if (detail::triangles_intersect(s.ids[i], s.corners[i], s.ids[j], s.corners[j])) return false;
                }
            }
        }
        const std::uint32_t removed[2] = {p.corner / 3, opposite_[p.corner] / 3};
        return visit_triangles(around_star, [&](const GridTriangle& t, const Box& box) {
            if (t.triangle == removed[0] || t.triangle == removed[1] || std::find(s.star.begin(), s.star.end(), t.triangle) != s.star.end()) {
                return true;  // the old star, replaced
            }
            const Ids& ids = triangles_[t.triangle];
            const FloatTriangle points = points_of(ids);
            if (slab.misses(points)) return true;  // (the new star lies within the slab)
            const detail::PreparedTriangle other(to_double(points));
            return s.box_columns.for_meeting(box, [&](std::size_t i) { return !detail::triangles_intersect(s.ids[i], s.prepared[i], ids, other); });
        });
    }

    /// The slab across the new fan's normal (the sum of its triangles' cross products) that
    /// holds the old and the new star: their points are the new star's corners (the link and the
    /// new position) and the edge's ends. Convex, so the box of both stars cut to it is too.
    Slab slab_around(const Plan& p, const Scratch& s) const {
        Slab slab;
        for (const detail::Triangle3& t : s.corners) {
            const Vec3d c = cross(sub(t[1], t[0]), sub(t[2], t[0]));
            for (int k = 0; k < 3; ++k) slab.axis[k] += c[k];
        }
        slab.origin = to_double(position_[p.corner]);
        for (const detail::Triangle3& t : s.corners) {
            for (const Vec3d& q : t) slab.add(q);
        }
        slab.add(point(vertex(next(p.corner)))), slab.add(point(vertex(prev(p.corner))));
        return slab;
    }

    FloatTriangle points_of(const Ids& t) const { return {positions_[t[0]], positions_[t[1]], positions_[t[2]]}; }

    /// Each vertex's component (triangles joined by shared vertices) and each component's
    /// enclosed volume (six times, the sum of its triangles' determinants).
    void measure_components() {
        detail::UnionFind sets(positions_.size());
        for (const Ids& t : triangles_) sets.unite(t[0], t[1]), sets.unite(t[0], t[2]);
        std::uint32_t count = 0;
        const std::vector<std::uint32_t> component = sets.labels(count);
        volume_.assign(count, 0);
        for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
            const Ids& ids = triangles_[t];
            summaries_[t].component = component[ids[0]];
            volume_[component[ids[0]]] += dot(point(ids[0]), cross(point(ids[1]), point(ids[2])));
        }
    }

    /// Six times the change of the enclosed volume the collapse of @a p makes: its new star (in
    /// @a s) less the triangles round both ends, both taken from the kept end's old position
    /// (they share their boundary, so the difference does not depend on the origin).
    double volume_change(const Plan& p, const Scratch& s) const {
        const Vec3d origin = point(vertex(next(p.corner)));
        const auto determinant = [&](const Vec3d& a, const Vec3d& b, const Vec3d& c) {
            return dot(sub(a, origin), cross(sub(b, origin), sub(c, origin)));
        };
        double change = 0;
        for (std::size_t i = 0; i < s.star.size(); ++i) {
            const Ids& old = triangles_[s.star[i]];
            change += determinant(s.corners[i][0], s.corners[i][1], s.corners[i][2]) -
                      determinant(point(old[0]), point(old[1]), point(old[2]));
        }
        for (const std::uint32_t t : {p.corner / 3, opposite_[p.corner] / 3}) {
            const Ids& old = triangles_[t];
            change -= determinant(point(old[0]), point(old[1]), point(old[2]));
        }
        return change;
    }

    /// The verdict on @a p, and the box of its new star.
    Verdict check(Plan& p, Scratch& s) const {
        if (!linked_new_star(p, s)) return Verdict::topology;
        if (!geometry_holds(s)) return Verdict::geometry;
        if (!intersection_free(p, s)) return Verdict::intersection;
        p.volume_change = volume_change(p, s);
        return Verdict::passed;
    }

    /// The collapse of the edge opposite @a corner, from a (kept) to b, whose triangles are
    /// t0 = (a, b, c) and t1 = (b, a, d): b's corners become a's, and the two edges left of each
    /// removed triangle are joined; the corners at a go to @a dirty. The corners c and d name
    /// are left to name_opposite_corners().
    void apply(std::uint32_t corner, std::vector<std::uint32_t>& dirty) {
        const std::uint32_t o = opposite_[corner];
        const std::uint32_t a = vertex(next(corner)), b = vertex(prev(corner));
        around(b, [&](std::uint32_t c) { triangles_[c / 3][c % 3] = a; });
        const std::uint32_t x0 = opposite_[next(corner)], y0 = opposite_[prev(corner)];  // across b-c and c-a
        const std::uint32_t x1 = opposite_[next(o)], y1 = opposite_[prev(o)];            // across a-d and d-b
        opposite_[x0] = y0, opposite_[y0] = x0;
        opposite_[x1] = y1, opposite_[y1] = x1;
        vertex_corner_[a] = next(y0);  // y0's triangle runs (., a, c)
        vertex_corner_[b] = kNone;
        alive_[corner / 3] = alive_[o / 3] = 0;
        moved_[corner / 3] = moved_[o / 3] = 1;  // (off the settled grid from now on)
        positions_[a] = position_[corner];
        quadrics_[a] = quadrics_[a] + quadrics_[b];
        around(a, [&](std::uint32_t c) { dirty.push_back(c); });
    }

    /// After apply(@a corner): a corner at c and at d off the removed triangles (whose
    /// opposite_ entries still name the corners across their edges).
    void name_opposite_corners(std::uint32_t corner) {
        const std::uint32_t o = opposite_[corner];
        vertex_corner_[vertex(corner)] = next(opposite_[next(corner)]);
        vertex_corner_[vertex(o)] = next(opposite_[next(o)]);
    }

    Mesh compact() const {
        Mesh mesh;
        std::vector<std::uint32_t> index(positions_.size(), kNone);
        for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
            if (!alive_[t]) continue;
            Ids ids = triangles_[t];
            for (std::uint32_t& v : ids) {
                if (index[v] == kNone) index[v] = std::uint32_t(mesh.vertices.size()), mesh.vertices.push_back(positions_[v]);
                v = index[v];
            }
            mesh.triangles.push_back(ids);
        }
        return mesh;
    }

    Array<std::array<float, 3>> positions_;
    Array<Ids> triangles_;
    Array<char> alive_;
    Array<std::uint32_t> opposite_;       ///< per corner
    Array<std::uint32_t> vertex_corner_;  ///< a corner at each vertex (kNone once removed)
    Array<Quadric> quadrics_;
    /// per corner, of the edge opposite it (from its lower vertex): the quadric error, and the
    /// cost (kNever at the corner where it runs from its higher vertex, or past the error bound)
    Array<double> cost_, error_;
    Array<std::array<float, 3>> position_;  ///< per corner: where that edge's collapse puts the vertex
    Array<char> rejected_;        ///< per corner: its edge's collapse failed a check since it last changed
    Array<Box> boxes_;            ///< per triangle
    Array<Summary> summaries_;    ///< per triangle: the directions it faces, its component
    std::vector<std::uint32_t> ring_corners_;  ///< the round's plans' corners round their ends (Plan::ring_begin)
    std::vector<std::uint32_t> dirty_;  ///< corners at the kept vertices of the round's collapses (their triangles to refresh)
    std::vector<std::vector<Candidate>> block_candidates_;  ///< gather_below() per block of triangles
    std::vector<Candidate> sort_buffer_;  ///< (sort_by_cost()'s, kept for its memory)
    Array<char> moved_;  ///< per triangle: changed (or removed) since settled_grid_ was built
    std::vector<std::uint32_t> moved_list_;  ///< those triangles (some removed since)
    std::vector<std::uint32_t> alive_list_;  ///< the alive triangles when settled_grid_ was built
    BoxGrid<GridTriangle> settled_grid_, moved_grid_;
    Box domain_ = empty_box();  ///< the box of the triangles when settled_grid_ was first built
    BoxGrid<GridPlan> plan_grid_;
    std::vector<double> volume_;            ///< per component: six times its enclosed volume
    std::size_t alive_count_;
    std::size_t target_;
    double max_error_squared_;
    bool closed_manifold_;
};

}  // namespace

Mesh decimate_mesh(const Mesh& mesh, const DecimateOptions& options, DecimateReport* report) {
    if (!(options.keep_fraction >= 0 && options.keep_fraction <= 1)) {
        throw UsageError("decimate: expected a share of triangles to keep in [0, 1], got " + std::to_string(options.keep_fraction));
    }
    if (!(options.max_error >= 0)) throw UsageError("decimate: expected a maximum error >= 0, got " + std::to_string(options.max_error));
    detail::check_indices(mesh);
    Decimator decimator(mesh, options);
    if (!decimator.closed_manifold()) check_closed_manifold(mesh);  // throws, naming the faults
    DecimateReport local;
    Mesh result = decimator.run(local);
    if (report) *report = local;
    return result;
}

}  // namespace vdbmesh
