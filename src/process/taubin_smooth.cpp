// taubin_smooth(): lambda/mu smoothing (G. Taubin, SIGGRAPH 1995) with uniform weights. Each step
// moves every vertex towards (lambda) or away from (mu) the mean of its neighbours, then the exact
// self-intersection test of geometry.h and the degenerate-face classification judge the moved
// mesh; the vertices of offending triangles are put back and the judgement repeated.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "vdbmesh/error.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/process.h"

namespace vdbmesh {
namespace {

/// Compressed neighbour lists: the vertices sharing an edge with each vertex.
struct Neighbours {
    std::vector<std::uint32_t> offsets, vertices;
};

Neighbours neighbours(const Mesh& mesh) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    edges.reserve(6 * mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            edges.emplace_back(t[k], t[(k + 1) % 3]);
            edges.emplace_back(t[(k + 1) % 3], t[k]);
        }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    Neighbours result;
    result.offsets.assign(mesh.vertices.size() + 1, 0);
    for (const auto& e : edges) ++result.offsets[e.first + 1];
    std::partial_sum(result.offsets.begin(), result.offsets.end(), result.offsets.begin());
    for (const auto& e : edges) result.vertices.push_back(e.second);
    return result;
}

using Positions = std::vector<std::array<float, 3>>;

Positions step(const Positions& from, const Neighbours& around, double factor) {
    Positions to(from.size());
    tbb::parallel_for(std::size_t{0}, from.size(), [&](std::size_t v) {
        const std::uint32_t begin = around.offsets[v], end = around.offsets[v + 1];
        to[v] = from[v];
        if (begin == end) return;
        for (int k = 0; k < 3; ++k) {
            double mean = 0;
            for (std::uint32_t i = begin; i < end; ++i) mean += from[around.vertices[i]][k];
            mean /= double(end - begin);
            to[v][k] = float(from[v][k] + factor * (mean - from[v][k]));
        }
    });
    return to;
}

/// Triangles of @a mesh that intersect another, or are degenerate but were regular before.
std::vector<std::uint32_t> offending_triangles(const Mesh& mesh, const std::vector<detail::FaceClass>& before) {
    std::vector<std::uint32_t> offending;
    for (const auto& [first, second] : find_self_intersections(mesh)) {
        offending.push_back(first);
        offending.push_back(second);
    }
    const std::vector<detail::FaceClass> now = detail::classify_faces(mesh);
    for (std::uint32_t i = 0; i < now.size(); ++i) {
        if (now[i] != detail::FaceClass::kRegular && before[i] == detail::FaceClass::kRegular) offending.push_back(i);
    }
    return offending;
}

/// Puts back the moved vertices of offending triangles until none is left; returns how many.
std::size_t hold_back(Mesh& moved, const Positions& previous, const std::vector<detail::FaceClass>& before) {
    std::size_t held = 0;
    for (;;) {
        std::size_t restored = 0;
        for (const std::uint32_t i : offending_triangles(moved, before)) {
            for (const std::uint32_t v : moved.triangles[i]) {
                if (moved.vertices[v] != previous[v]) moved.vertices[v] = previous[v], ++restored;
            }
        }
        if (restored == 0) return held;  // what is left was there before the step
        held += restored;
    }
}

}  // namespace

Mesh taubin_smooth(const Mesh& mesh, const TaubinOptions& options, TaubinReport* report) {
    if (options.iterations < 0) throw UsageError("Taubin iterations: expected >= 0, got " + std::to_string(options.iterations));
    if (!std::isfinite(options.lambda) || !std::isfinite(options.mu)) throw UsageError("Taubin factors: expected finite numbers");
    detail::check_indices(mesh);
    const Neighbours around = neighbours(mesh);
    const std::vector<detail::FaceClass> before = detail::classify_faces(mesh);
    Mesh result = mesh;
    TaubinReport local;
    for (int i = 0; i < 2 * options.iterations; ++i) {
        const Positions previous = result.vertices;
        result.vertices = step(previous, around, i % 2 == 0 ? options.lambda : options.mu);
        local.held_back += hold_back(result, previous, before);
    }
    if (report) *report = local;
    return result;
}

}  // namespace vdbmesh
