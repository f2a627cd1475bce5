// decimate_mesh(): quadric edge collapse (M. Garland and P. Heckbert, SIGGRAPH 1997) that keeps a
// closed manifold mesh closed, manifold, oriented and free of self-intersections. Edges are
// collapsed cheapest first (a heap with lazy deletion: an entry is stale once either end has
// changed). Each collapse is checked where it changes the mesh, on the float coordinates that
// will be written:
// - topology: the link condition (the ends' neighbours in common are exactly the two opposite
//   corners; T. K. Dey et al., "Topology preserving edge contraction", 1999), which keeps a
//   closed 2-manifold one;
// - geometry: no triangle of the new star is degenerate (exact collinearity) or turns by more
//   than kMaxTurnDegrees;
// - intersections: each new triangle against the others of the star and against the triangles
//   a hash grid finds near it, with the exact tests of `vdbmesh check` (triangle_intersection.h).
#include <algorithm>
#include <cmath>
#include <queue>
#include <string>

#include "process/quadric.h"
#include "process/triangle_hash.h"
#include "vdbmesh/error.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/process.h"

namespace vdbmesh {
namespace {

using detail::Quadric;
using detail::Vec3d;
using Ids = std::array<std::uint32_t, 3>;

constexpr double kMaxTurnDegrees = 75;  ///< largest change of a triangle's normal in one collapse
constexpr double kCellEdges = 2;        ///< hash cell size in mean edge lengths
/// Ties of the quadric error (flat regions, where it is 0) go to the shorter edge, which keeps
/// the triangles there from growing into needles.
constexpr double kLengthWeight = 1e-3;

Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3d cross(const Vec3d& a, const Vec3d& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3d to_double(const std::array<float, 3>& p) { return {p[0], p[1], p[2]}; }
std::array<float, 3> to_float(const Vec3d& p) { return {float(p[0]), float(p[1]), float(p[2])}; }

bool boxes_overlap(const detail::TriangleHash::Box& a, const detail::TriangleHash::Box& b) {
    for (int k = 0; k < 3; ++k) {
        if (a[1][k] < b[0][k] || b[1][k] < a[0][k]) return false;
    }
    return true;
}

/// An edge waiting in the heap, with the versions of its ends when it was pushed.
struct Candidate {
    double cost;   ///< the quadric error plus kLengthWeight times the squared edge length
    double error;  ///< the quadric error (squared world units)
    std::uint32_t a, b, version_a, version_b;
    bool operator<(const Candidate& o) const {  // the heap's top is the cheapest
        if (cost != o.cost) return cost > o.cost;
        return a != o.a ? a > o.a : b > o.b;
    }
};

void check_closed_manifold(const Mesh& mesh) {
    const detail::Topology topology = detail::analyze_topology(mesh);
    if (topology.boundary_edges || topology.nonmanifold_edges || topology.nonmanifold_vertices || topology.misoriented_edges) {
        throw Error("decimate: expected a closed, manifold, consistently oriented mesh, got " +
                    std::to_string(topology.boundary_edges) + " boundary edges, " + std::to_string(topology.nonmanifold_edges) +
                    " non-manifold edges, " + std::to_string(topology.nonmanifold_vertices) + " non-manifold vertices, " +
                    std::to_string(topology.misoriented_edges) + " misoriented edges");
    }
}

class Decimator {
public:
    Decimator(const Mesh& mesh, const DecimateOptions& options)
        : positions_(mesh.vertices), triangles_(mesh.triangles), alive_(mesh.triangles.size(), 1),
          around_(mesh.vertices.size()), quadrics_(mesh.vertices.size()), versions_(mesh.vertices.size(), 0),
          excluded_(mesh.triangles.size(), 0), hash_(cell_size(mesh)), alive_count_(mesh.triangles.size()),
          max_error_squared_(options.max_error * options.max_error) {
        target_ = std::size_t(std::ceil(options.keep_fraction * double(mesh.triangles.size())));
        for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
            for (const std::uint32_t v : triangles_[t]) around_[v].push_back(t);
            hash_.insert(t, box(triangles_[t]));
            const Vec3d n = normal(triangles_[t]);
            const double length = std::sqrt(dot(n, n));
            if (length == 0) continue;
            const Quadric plane = Quadric::plane({n[0] / length, n[1] / length, n[2] / length}, point(triangles_[t][0]));
            for (const std::uint32_t v : triangles_[t]) quadrics_[v] = quadrics_[v] + plane;
        }
        for (const Ids& t : triangles_) {
            for (int k = 0; k < 3; ++k) {
                if (t[k] < t[(k + 1) % 3]) push(t[k], t[(k + 1) % 3]);  // each edge once in a closed oriented mesh
            }
        }
    }

    Mesh run(DecimateReport& report) {
        while (alive_count_ > target_ && !heap_.empty()) {
            const Candidate c = heap_.top();
            heap_.pop();
            if (versions_[c.a] != c.version_a || versions_[c.b] != c.version_b || around_[c.a].empty() || around_[c.b].empty()) continue;
            if (c.error > max_error_squared_) continue;  // a longer edge with less error may follow
            if (collapse(c.a, c.b, placement(c.a, c.b), report)) {
                ++report.collapses;
                report.max_error = std::max(report.max_error, std::sqrt(c.error));
            }
        }
        return compact();
    }

private:
    static double cell_size(const Mesh& mesh) {
        double total = 0;
        for (const Ids& t : mesh.triangles) {
            for (int k = 0; k < 3; ++k) {
                const Vec3d d = sub(to_double(mesh.vertices[t[k]]), to_double(mesh.vertices[t[(k + 1) % 3]]));
                total += std::sqrt(dot(d, d));
            }
        }
        const double mean = mesh.triangles.empty() ? 1 : total / double(3 * mesh.triangles.size());
        return mean > 0 ? kCellEdges * mean : 1;
    }

    Vec3d point(std::uint32_t v) const { return to_double(positions_[v]); }
    Vec3d normal(const Ids& t) const { return cross(sub(point(t[1]), point(t[0])), sub(point(t[2]), point(t[0]))); }

    detail::TriangleHash::Box box(const Ids& t) const { return box(corners(t, ~0u, {})); }

    /// The box of float corners (exactly representable: the corners are floats).
    static detail::TriangleHash::Box box(const detail::Triangle3& c) {
        detail::TriangleHash::Box b{to_float(c[0]), to_float(c[0])};
        for (const Vec3d& q : c) {
            for (int k = 0; k < 3; ++k) b[0][k] = std::min(b[0][k], float(q[k])), b[1][k] = std::max(b[1][k], float(q[k]));
        }
        return b;
    }

    /// Where the collapse of (a, b) puts the vertex, rounded to floats: the quadric's minimizer
    /// when it is defined and near the edge, else the best of the ends and the midpoint.
    std::array<float, 3> placement(std::uint32_t a, std::uint32_t b) const {
        const Quadric q = quadrics_[a] + quadrics_[b];
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

    void push(std::uint32_t a, std::uint32_t b) {
        const std::array<float, 3> p = placement(a, b);
        const double error = (quadrics_[a] + quadrics_[b]).error(to_double(p));
        const Vec3d edge = sub(point(a), point(b));
        heap_.push({error + kLengthWeight * dot(edge, edge), error, a, b, versions_[a], versions_[b]});
    }

    /// The vertices sharing a triangle with @a v, sorted.
    std::vector<std::uint32_t> ring(std::uint32_t v) const {
        std::vector<std::uint32_t> result;
        for (const std::uint32_t t : around_[v]) {
            for (const std::uint32_t w : triangles_[t]) {
                if (w != v) result.push_back(w);
            }
        }
        std::sort(result.begin(), result.end());
        result.erase(std::unique(result.begin(), result.end()), result.end());
        return result;
    }

    /// The two triangles on edge (a, b), or false when the edge does not have exactly two.
    bool edge_triangles(std::uint32_t a, std::uint32_t b, std::array<std::uint32_t, 2>& edge) const {
        int found = 0;
        for (const std::uint32_t t : around_[a]) {
            const Ids& ids = triangles_[t];
            if (ids[0] != b && ids[1] != b && ids[2] != b) continue;
            if (found == 2) return false;
            edge[found++] = t;
        }
        return found == 2;
    }

    bool link_condition(std::uint32_t a, std::uint32_t b, const std::array<std::uint32_t, 2>& edge) const {
        const std::vector<std::uint32_t> ra = ring(a), rb = ring(b);
        std::vector<std::uint32_t> common;
        std::set_intersection(ra.begin(), ra.end(), rb.begin(), rb.end(), std::back_inserter(common));
        std::vector<std::uint32_t> opposite;
        for (const std::uint32_t t : edge) {
            for (const std::uint32_t w : triangles_[t]) {
                if (w != a && w != b) opposite.push_back(w);
            }
        }
        std::sort(opposite.begin(), opposite.end());
        return common == opposite && opposite[0] != opposite[1];
    }

    /// The star after the collapse: each triangle around a or b but off the edge (so around
    /// exactly one of them), b renamed a.
    std::vector<std::pair<std::uint32_t, Ids>> new_star(std::uint32_t a, std::uint32_t b, const std::array<std::uint32_t, 2>& edge) const {
        std::vector<std::pair<std::uint32_t, Ids>> star;
        for (const std::uint32_t v : {a, b}) {
            for (const std::uint32_t t : around_[v]) {
                if (t == edge[0] || t == edge[1]) continue;
                Ids ids = triangles_[t];
                for (std::uint32_t& w : ids) w = w == b ? a : w;
                star.emplace_back(t, ids);
            }
        }
        return star;
    }

    detail::Triangle3 corners(const Ids& ids, std::uint32_t moved, const Vec3d& p) const {
        detail::Triangle3 result;
        for (int k = 0; k < 3; ++k) result[k] = ids[k] == moved ? p : point(ids[k]);
        return result;
    }

    bool geometry_holds(const std::vector<std::pair<std::uint32_t, Ids>>& star, std::uint32_t a, const Vec3d& p) const {
        const double min_cosine = std::cos(kMaxTurnDegrees * 3.14159265358979323846 / 180);
        for (const auto& [t, ids] : star) {
            const detail::Triangle3 c = corners(ids, a, p);
            if (detail::collinear(c[0], c[1], c[2])) return false;
            const Vec3d before = normal(triangles_[t]), after = cross(sub(c[1], c[0]), sub(c[2], c[0]));
            if (dot(before, after) < min_cosine * std::sqrt(dot(before, before) * dot(after, after))) return false;
        }
        return true;
    }

    /// The new triangles cross neither each other nor any triangle near them outside the star
    /// (gathered once from the hash grid over the star's box).
    bool intersection_free(const std::vector<std::pair<std::uint32_t, Ids>>& star, std::uint32_t a, const Vec3d& p,
                           const std::array<std::uint32_t, 2>& edge) {
        const std::uint32_t changing = ++stamp_;
        for (const auto& [t, ids] : star) excluded_[t] = changing;
        excluded_[edge[0]] = excluded_[edge[1]] = changing;
        std::vector<detail::Triangle3> corners_of(star.size());
        std::vector<detail::TriangleHash::Box> boxes(star.size());
        detail::TriangleHash::Box around = box(corners(star[0].second, a, p));
        for (std::size_t i = 0; i < star.size(); ++i) {
            corners_of[i] = corners(star[i].second, a, p);
            boxes[i] = box(corners_of[i]);
            for (int k = 0; k < 3; ++k) around[0][k] = std::min(around[0][k], boxes[i][0][k]), around[1][k] = std::max(around[1][k], boxes[i][1][k]);
            for (std::size_t j = 0; j < i; ++j) {
                if (detail::triangles_intersect(star[i].second, corners_of[i], star[j].second, corners_of[j])) return false;
            }
        }
        nearby_.clear();
        hash_.visit(around, [&](std::uint32_t u) {
            if (excluded_[u] == changing) return;
            excluded_[u] = changing;  // each candidate once
            nearby_.push_back(u);
        });
        for (const std::uint32_t u : nearby_) {
            const detail::Triangle3 other = corners(triangles_[u], a, p);
            const detail::TriangleHash::Box other_box = box(other);
            for (std::size_t i = 0; i < star.size(); ++i) {
                if (boxes_overlap(boxes[i], other_box) && detail::triangles_intersect(star[i].second, corners_of[i], triangles_[u], other)) return false;
            }
        }
        return true;
    }

    bool collapse(std::uint32_t a, std::uint32_t b, const std::array<float, 3>& position, DecimateReport& report) {
        std::array<std::uint32_t, 2> edge{};
        if (!edge_triangles(a, b, edge) || !link_condition(a, b, edge)) {
            ++report.rejected_topology;
            return false;
        }
        const Vec3d p = to_double(position);
        const auto star = new_star(a, b, edge);
        if (!geometry_holds(star, a, p)) {
            ++report.rejected_geometry;
            return false;
        }
        if (!intersection_free(star, a, p, edge)) {
            ++report.rejected_intersection;
            return false;
        }
        apply(a, b, position, star, edge);
        return true;
    }

    void apply(std::uint32_t a, std::uint32_t b, const std::array<float, 3>& position,
               const std::vector<std::pair<std::uint32_t, Ids>>& star, const std::array<std::uint32_t, 2>& edge) {
        for (const std::uint32_t t : edge) {
            hash_.erase(t, box(triangles_[t]));
            alive_[t] = 0;
            for (const std::uint32_t v : triangles_[t]) {
                auto& list = around_[v];
                list.erase(std::remove(list.begin(), list.end(), t), list.end());
            }
        }
        alive_count_ -= 2;
        for (const auto& [t, ids] : star) hash_.erase(t, box(triangles_[t]));
        positions_[a] = position;
        quadrics_[a] = quadrics_[a] + quadrics_[b];
        around_[a].clear();
        for (const auto& [t, ids] : star) {
            triangles_[t] = ids;
            around_[a].push_back(t);
            hash_.insert(t, box(ids));
        }
        around_[b].clear();
        ++versions_[a];
        ++versions_[b];
        for (const std::uint32_t w : ring(a)) push(std::min(a, w), std::max(a, w));
    }

    Mesh compact() const {
        Mesh mesh;
        std::vector<std::uint32_t> index(positions_.size(), ~0u);
        for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
            if (!alive_[t]) continue;
            Ids ids = triangles_[t];
            for (std::uint32_t& v : ids) {
                if (index[v] == ~0u) index[v] = std::uint32_t(mesh.vertices.size()), mesh.vertices.push_back(positions_[v]);
                v = index[v];
            }
            mesh.triangles.push_back(ids);
        }
        return mesh;
    }

    std::vector<std::array<float, 3>> positions_;
    std::vector<Ids> triangles_;
    std::vector<char> alive_;
    std::vector<std::vector<std::uint32_t>> around_;  ///< the alive triangles around each vertex
    std::vector<Quadric> quadrics_;
    std::vector<std::uint32_t> versions_;
    std::vector<std::uint32_t> excluded_;  ///< stamp of the collapse that last looked at the triangle
    std::vector<std::uint32_t> nearby_;    ///< the triangles near the star being checked
    std::uint32_t stamp_ = 0;
    detail::TriangleHash hash_;
    std::priority_queue<Candidate> heap_;
    std::size_t alive_count_;
    std::size_t target_ = 0;
    double max_error_squared_;
};

}  // namespace

Mesh decimate_mesh(const Mesh& mesh, const DecimateOptions& options, DecimateReport* report) {
    if (!(options.keep_fraction >= 0 && options.keep_fraction <= 1)) {
        throw UsageError("decimate: expected a share of triangles to keep in [0, 1], got " + std::to_string(options.keep_fraction));
    }
    if (!(options.max_error >= 0)) throw UsageError("decimate: expected a maximum error >= 0, got " + std::to_string(options.max_error));
    detail::check_indices(mesh);
    check_closed_manifold(mesh);
    DecimateReport local;
    Mesh result = Decimator(mesh, options).run(local);
    if (report) *report = local;
    return result;
}

}  // namespace vdbmesh
