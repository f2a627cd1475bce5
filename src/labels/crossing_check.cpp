// The local exact crossing check (crossing_check.h).

#include "labels/crossing_check.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>

#include "vdbmesh/geometry.h"

namespace vdbmesh::labels_detail {
namespace {

using detail::Box;

std::array<std::int64_t, 3> cell_of(const std::array<float, 3>& p, double cell) {
    return {std::int64_t(std::floor(p[0] / cell)), std::int64_t(std::floor(p[1] / cell)), std::int64_t(std::floor(p[2] / cell))};
}

/// 21 bits per axis, enough for 2 million cells along each (a key collision only costs tests).
std::uint64_t key_of(const std::array<std::int64_t, 3>& c) {
    const auto bits = [](std::int64_t v) { return std::uint64_t(v) & 0x1FFFFF; };
    return bits(c[0]) | bits(c[1]) << 21 | bits(c[2]) << 42;
}

template <class Visit>
void for_each_cell(const Box& box, double cell, Visit&& visit) {
    const auto lo = cell_of(box.lo, cell), hi = cell_of(box.hi, cell);
    for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
        for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
            for (std::int64_t x = lo[0]; x <= hi[0]; ++x) visit(key_of({x, y, z}));
}

detail::Triangle3 corners(const Mesh& mesh, std::uint32_t t) {
    const auto& tri = mesh.triangles[t];
    detail::Triangle3 c;
    for (int i = 0; i < 3; ++i) c[i] = {mesh.vertices[tri[i]][0], mesh.vertices[tri[i]][1], mesh.vertices[tri[i]][2]};
    return c;
}

}  // namespace

std::vector<std::uint8_t> crossing_triangles(const Mesh& mesh, const std::vector<std::uint32_t>& subset, double cell) {
    const std::size_t n = mesh.triangles.size();
    std::vector<Box> boxes(n);
    std::vector<std::uint8_t> degenerate(n, 0);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t t) {
        boxes[t] = detail::triangle_box(mesh, std::uint32_t(t));
        const detail::Triangle3 c = corners(mesh, std::uint32_t(t));
        degenerate[t] = detail::collinear(c[0], c[1], c[2]);
    });
    std::vector<std::pair<std::uint64_t, std::uint32_t>> cells;
    cells.reserve(2 * n);
    for (std::uint32_t t = 0; t < n; ++t) for_each_cell(boxes[t], cell, [&](std::uint64_t key) { cells.push_back({key, t}); });
    tbb::parallel_sort(cells.begin(), cells.end());

    std::vector<std::uint8_t> asked(n, 0);
    for (std::uint32_t t : subset) asked[t] = 1;
    // Runs of one cell; each pair is tested in one cell only: the one holding the low corner of
    // the overlap of the two boxes (both boxes reach it, so both are listed there).
    std::vector<std::size_t> runs;
    for (std::size_t i = 0; i < cells.size(); ++i)
        if (i == 0 || cells[i].first != cells[i - 1].first) runs.push_back(i);
    runs.push_back(cells.size());
    tbb::enumerable_thread_specific<std::vector<std::uint32_t>> found;
    tbb::parallel_for(std::size_t(0), runs.size() - 1, [&](std::size_t r) {
        std::vector<std::uint32_t>& out = found.local();
        for (std::size_t i = runs[r]; i < runs[r + 1]; ++i) {
            const std::uint32_t t = cells[i].second;
            if (degenerate[t]) {
                if (asked[t]) out.push_back(t);
                continue;
            }
            const detail::Triangle3 c = corners(mesh, t);
            for (std::size_t j = i + 1; j < runs[r + 1]; ++j) {
                const std::uint32_t u = cells[j].second;
                if ((!asked[t] && !asked[u]) || degenerate[u] || !detail::boxes_overlap(boxes[t], boxes[u])) continue;
                const std::array<float, 3> low{std::max(boxes[t].lo[0], boxes[u].lo[0]), std::max(boxes[t].lo[1], boxes[u].lo[1]),
                                               std::max(boxes[t].lo[2], boxes[u].lo[2])};
                if (key_of(cell_of(low, cell)) != cells[i].first) continue;
                if (detail::triangles_intersect(mesh.triangles[t], c, mesh.triangles[u], corners(mesh, u))) out.push_back(t), out.push_back(u);
            }
        }
    });
    std::vector<std::uint8_t> flagged(n, 0);
    for (const auto& list : found)
        for (std::uint32_t t : list) flagged[t] = 1;
    return flagged;
}

}  // namespace vdbmesh::labels_detail
