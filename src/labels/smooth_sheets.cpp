// Constrained smoothing of the multi-label surface and the hold-back that keeps it free of
// crossings (smooth_sheets.h).

#include "labels/smooth_sheets.h"

#include "labels/crossing_check.h"
#include "labels/label_components.h"
#include "labels/restore_volumes.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "vdbmesh/error.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh::labels_detail {
namespace {

/// A move is halved this many times before the vertex goes back to its unsmoothed place.
constexpr int kHalvings = 5;
constexpr int kMaxRounds = kHalvings + 3;
/// The volume the held-back vertices lose is made up by the free ones this many steps from them.
constexpr int kMakeUpRings = 6;

/// Neighbours along the quads' sides, per vertex (compressed rows, each sorted).
struct Neighbours {
    std::vector<std::uint32_t> start, list;
};

Neighbours quad_neighbours(std::size_t vertex_count, const std::vector<SheetQuad>& quads) {
    Neighbours n;
    n.start.assign(vertex_count + 1, 0);
    for (const SheetQuad& q : quads)
        for (std::uint32_t v : q.vertex) n.start[v + 1] += 2;
    for (std::size_t v = 0; v < vertex_count; ++v) n.start[v + 1] += n.start[v];
    n.list.resize(n.start.back());
    std::vector<std::uint32_t> fill(n.start.begin(), n.start.end() - 1);
    for (const SheetQuad& q : quads)
        for (int k = 0; k < 4; ++k) {
            const std::uint32_t v = q.vertex[k];
            n.list[fill[v]++] = q.vertex[(k + 1) % 4];
            n.list[fill[v]++] = q.vertex[(k + 3) % 4];
        }
    // Each side is shared by the walls round it: keep each neighbour once.
    std::vector<std::uint32_t> unique_start(vertex_count + 1, 0);
    std::vector<std::uint32_t> unique_list;
    unique_list.reserve(n.list.size() / 2);
    for (std::size_t v = 0; v < vertex_count; ++v) {
        auto begin = n.list.begin() + n.start[v], end = n.list.begin() + n.start[v + 1];
        std::sort(begin, end);
        unique_list.insert(unique_list.end(), begin, std::unique(begin, end));
        unique_start[v + 1] = std::uint32_t(unique_list.size());
    }
    return {std::move(unique_start), std::move(unique_list)};
}

std::vector<Point> smoothed_places(const SheetVertices& vertices, const Neighbours& n, const LabelMeshOptions& options) {
    std::vector<Point> place = vertices.base, next(place.size());
    const double offset = options.max_offset;
    for (int pass = 0; pass < options.smoothing_iterations; ++pass) {
        tbb::parallel_for(std::size_t(0), place.size(), [&](std::size_t v) {
            Point mean{0, 0, 0};
            for (std::uint32_t i = n.start[v]; i < n.start[v + 1]; ++i)
                for (int k = 0; k < 3; ++k) mean[k] += place[n.list[i]][k];
            const double count = double(n.start[v + 1] - n.start[v]);
            for (int k = 0; k < 3; ++k)
                next[v][k] = std::clamp(mean[k] / count, vertices.corner[v][k] - offset,
                                        vertices.corner[v][k] + offset);
        });
        place.swap(next);
    }
    return place;
}

double squared_distance(const Point& a, const Point& b) {
    double d = 0;
    for (int k = 0; k < 3; ++k) d += (a[k] - b[k]) * (a[k] - b[k]);
    return d;
}

/// Two triangles per quad, along the shorter diagonal of the smoothed places.
void split_quads(const std::vector<SheetQuad>& quads, const std::vector<Point>& place, bool mirrored, LabelSurface& out) {
    out.mesh.triangles.resize(2 * quads.size());
    out.sides.resize(2 * quads.size());
    tbb::parallel_for(std::size_t(0), quads.size(), [&](std::size_t i) {
        const auto& v = quads[i].vertex;
        const bool diagonal02 = squared_distance(place[v[0]], place[v[2]]) <= squared_distance(place[v[1]], place[v[3]]);
        std::array<std::uint32_t, 3> a = diagonal02 ? std::array<std::uint32_t, 3>{v[0], v[1], v[2]} : std::array<std::uint32_t, 3>{v[0], v[1], v[3]};
        std::array<std::uint32_t, 3> b = diagonal02 ? std::array<std::uint32_t, 3>{v[0], v[2], v[3]} : std::array<std::uint32_t, 3>{v[1], v[2], v[3]};
        if (mirrored) std::swap(a[1], a[2]), std::swap(b[1], b[2]);
        out.mesh.triangles[2 * i] = a;
        out.mesh.triangles[2 * i + 1] = b;
        out.sides[2 * i] = out.sides[2 * i + 1] = quads[i].sides;
    });
}

bool is_mirroring(const Affine& m) {
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    return det < 0;
}

void place_in_world(const SheetVertices& vertices, const std::vector<Point>& smoothed, const std::vector<double>& share,
                    const Affine& m, Mesh& mesh) {
    mesh.vertices.resize(smoothed.size());
    tbb::parallel_for(std::size_t(0), smoothed.size(), [&](std::size_t v) {
        Point p;
        for (int k = 0; k < 3; ++k) p[k] = vertices.base[v][k] + share[v] * (smoothed[v][k] - vertices.base[v][k]);
        for (int r = 0; r < 3; ++r) mesh.vertices[v][r] = float(m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3]);
    });
}

/// A grid cell for the CrossingCheck: about half a triangle's reach (its corners lie within
/// max_offset of corners one voxel apart), so a cell holds few triangles and a triangle
/// reaches a few cells. The check is exact whatever the size; this only sets the work.
double check_cell(const Affine& m, double max_offset) {
    double longest = 0;
    for (int k = 0; k < 3; ++k) longest = std::max(longest, std::sqrt(m[0][k] * m[0][k] + m[1][k] * m[1][k] + m[2][k] * m[2][k]));
    return (0.5 + max_offset) * longest;
}

/// The vertices (ascending) of the triangles that cross another or degenerate (among the pairs
/// @a check tests: with a triangle of @a moved after its first check), and of label pieces
/// turned inside out (which no crossing would show).
std::vector<std::uint32_t> offending_vertices(const Mesh& mesh, CrossingCheck& check, const std::vector<std::uint32_t>& moved,
                                              const LabelComponents& pieces, const std::vector<double>& base_volumes) {
    std::vector<std::uint8_t> bad = pieces.inverted(mesh, base_volumes);
    const std::vector<std::uint8_t> crossing = check.crossing_triangles(mesh, moved);
    for (std::size_t t = 0; t < crossing.size(); ++t)
        if (crossing[t])
            for (std::uint32_t v : mesh.triangles[t]) bad[v] = 1;
    std::vector<std::uint32_t> list;
    for (std::uint32_t v = 0; v < bad.size(); ++v)
        if (bad[v]) list.push_back(v);
    return list;
}

/// The triangles (ascending) with a corner among @a vertices (ascending).
std::vector<std::uint32_t> triangles_at(const Mesh& mesh, const std::vector<std::uint32_t>& vertices) {
    std::vector<std::uint8_t> moved(mesh.vertices.size(), 0);
    for (std::uint32_t v : vertices) moved[v] = 1;
    std::vector<std::uint32_t> list;
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        if (moved[tri[0]] || moved[tri[1]] || moved[tri[2]]) list.push_back(t);
    }
    return list;
}

/// The vertices at most @a rings steps along the walls from one of @a from.
std::vector<std::uint8_t> near(const Neighbours& n, std::vector<std::uint8_t> from, int rings) {
    for (int ring = 0; ring < rings; ++ring) {
        std::vector<std::uint8_t> next = from;
        tbb::parallel_for(std::size_t(0), from.size(), [&](std::size_t v) {
            for (std::uint32_t i = n.start[v]; i < n.start[v + 1] && !next[v]; ++i) next[v] = from[n.list[i]];
        });
        from.swap(next);
    }
    return from;
}

/// The vertices (ascending) whose place in @a mesh differs from @a before (bit for bit).
std::vector<std::uint32_t> moved_vertices(const Mesh& mesh, const std::vector<std::array<float, 3>>& before) {
    std::vector<std::uint32_t> list;
    for (std::uint32_t v = 0; v < before.size(); ++v)
        if (mesh.vertices[v] != before[v]) list.push_back(v);
    return list;
}

/// Holds vertices back toward their unsmoothed place (halving @a share, at last to 0) until no
/// triangle crosses another, degenerates or turns a piece inside out; places out.mesh.
/// Returns the rounds taken.
/// @a subset: the triangles moved since @a check's last call (none before its first, which
/// tests every triangle); later rounds test those round the vertices just moved back.
int hold_back(const SheetVertices& vertices, const std::vector<Point>& smoothed, std::vector<double>& share,
              const Affine& index_to_world, CrossingCheck& check, std::vector<std::uint32_t> subset, const LabelComponents& pieces,
              const std::vector<double>& base_volumes, LabelSurface& out) {
    for (int round = 0;; ++round) {
        place_in_world(vertices, smoothed, share, index_to_world, out.mesh);
        const std::vector<std::uint32_t> bad = offending_vertices(out.mesh, check, subset, pieces, base_volumes);
        if (bad.empty()) return round;
        bool moved = false;
        for (std::uint32_t v : bad) {
            moved = moved || share[v] > 0;
            share[v] = round + 1 >= kHalvings ? 0.0 : share[v] / 2;
        }
        if (!moved || round + 1 >= kMaxRounds)
            throw Error("label mesher: " + std::to_string(bad.size()) +
                        " vertices still on crossing or degenerate triangles at their unsmoothed places (a bug)");
        subset = triangles_at(out.mesh, bad);
    }
}

}  // namespace

void smooth_sheets(const SheetVertices& vertices, const std::vector<SheetQuad>& quads, const std::vector<std::uint64_t>& voxels,
                   const LabelMeshOptions& options,
                   const Affine& index_to_world, LabelSurface& out, const std::function<void(double)>& progress) {
    using Clock = std::chrono::steady_clock;
    const auto phase = [&](const char* name, Clock::time_point start) {
        out.phases.emplace_back(name, std::chrono::duration<double>(Clock::now() - start).count());
    };
    Clock::time_point start = Clock::now();
    const Neighbours neighbours = quad_neighbours(vertices.base.size(), quads);
    std::vector<Point> smoothed = smoothed_places(vertices, neighbours, options);
    phase("smooth", start);
    start = Clock::now();
    restore_volumes(smoothed, vertices, quads, voxels, options.max_offset, {});
    phase("volumes", start);
    if (progress) progress(0.6);
    start = Clock::now();
    split_quads(quads, smoothed, is_mirroring(index_to_world), out);
    std::vector<double> share(smoothed.size(), 0.0);
    place_in_world(vertices, smoothed, share, index_to_world, out.mesh);
    const LabelComponents pieces(out.mesh, out.sides);
    const std::vector<double> base_volumes = pieces.volumes(out.mesh);
    share.assign(smoothed.size(), 1.0);
    CrossingCheck check(check_cell(index_to_world, options.max_offset));
    out.hold_back_rounds = hold_back(vertices, smoothed, share, index_to_world, check, {}, pieces, base_volumes, out);
    phase("hold back", start);
    if (progress) progress(0.8);
    // Vertices held back lose some of the volume put back; the free vertices near them (the
    // loss is local) make it up, the others stay, and the check goes on from where it stopped,
    // testing the triangles that moved.
    std::vector<std::uint8_t> held(share.size(), 0);
    for (std::size_t v = 0; v < share.size(); ++v) held[v] = share[v] < 1;
    if (std::find(held.begin(), held.end(), 1) != held.end()) {
        start = Clock::now();
        for (std::size_t v = 0; v < share.size(); ++v)
            for (int k = 0; k < 3; ++k) smoothed[v][k] = vertices.base[v][k] + share[v] * (smoothed[v][k] - vertices.base[v][k]);
        std::vector<std::uint8_t> fixed = near(neighbours, held, kMakeUpRings);
        for (std::size_t v = 0; v < fixed.size(); ++v) fixed[v] = held[v] || !fixed[v];
        restore_volumes(smoothed, vertices, quads, voxels, options.max_offset, fixed);
        const std::vector<std::array<float, 3>> before = out.mesh.vertices;
        share.assign(smoothed.size(), 1.0);
        place_in_world(vertices, smoothed, share, index_to_world, out.mesh);
        const std::vector<std::uint32_t> moved = triangles_at(out.mesh, moved_vertices(out.mesh, before));
        out.hold_back_rounds += hold_back(vertices, smoothed, share, index_to_world, check, moved, pieces, base_volumes, out);
        phase("volumes again", start);
    }
    out.vertices_held_back = std::size_t(std::count_if(held.begin(), held.end(), [](std::uint8_t h) { return h; }) +
                                         std::count_if(share.begin(), share.end(), [](double s) { return s < 1; }));
}

}  // namespace vdbmesh::labels_detail
