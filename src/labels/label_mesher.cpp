// mesh_labels(): the multi-label dual mesh (labels.h). One vertex per sheet of walls through a
// voxel corner (corner_sheets.h), one quad per pair of face-adjacent voxels with different
// labels, split into two triangles; vertices smoothed within their box round the corner
// (smooth_sheets.h), held back where a triangle would cross another.

#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "labels/label_grid.h"
#include "labels/smooth_sheets.h"
#include "vdbmesh/error.h"
#include "vdbmesh/labels.h"

namespace vdbmesh {
namespace {

using namespace labels_detail;
using Clock = std::chrono::steady_clock;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

labels_detail::LabelGrid make_grid(const LabelVolume& volume, const LabelMeshOptions& options, std::vector<std::uint32_t>& meshed) {
    LabelGrid grid;
    grid.dims = volume.header.dims;
    grid.meshed.assign(std::size_t(kMaxLabel) + 1, 0);
    if (options.labels.empty()) {
        for (const LabelCount& count : count_labels(volume))
            if (count.value != 0) grid.meshed[count.value] = 1;
    } else {
        for (std::uint32_t label : options.labels) {
            if (label == 0 || label > kMaxLabel) throw UsageError("--labels: expected values 1.." + std::to_string(kMaxLabel) + ", got " + std::to_string(label));
            grid.meshed[label] = 1;
        }
    }
    grid.labels.resize(volume.labels.size());
    for (std::size_t i = 0; i < volume.labels.size(); ++i) grid.labels[i] = grid.meshed[volume.labels[i]] ? volume.labels[i] : 0;
    std::vector<std::uint8_t> present(std::size_t(kMaxLabel) + 1, 0);
    for (std::uint16_t label : grid.labels) present[label] = 1;
    for (std::uint32_t v = 1; v <= kMaxLabel; ++v)
        if (grid.meshed[v] && present[v]) meshed.push_back(v);
    return grid;
}

/// Per corner its first vertex (kNone: no wall there), and per vertex its unsmoothed place:
/// the corner itself, or for several sheets each moved toward the middle of its walls.
void number_vertices(const LabelGrid& grid, std::vector<std::uint32_t>& first, SheetVertices& vertices) {
    const std::array<std::int64_t, 3> n = grid.corner_dims();
    first.assign(std::size_t(n[0] * n[1] * n[2]), kNone);
    std::vector<std::uint32_t> layer_count(std::size_t(n[2]), 0);
    tbb::parallel_for(std::int64_t(0), n[2], [&](std::int64_t c) {
        std::uint32_t count = 0;
        for (std::int64_t b = 0; b < n[1]; ++b)
            for (std::int64_t a = 0; a < n[0]; ++a) {
                const int sheets = grid.sheets(a, b, c).count;
                if (sheets) first[grid.corner_index(a, b, c)] = count, count += std::uint32_t(sheets);
            }
        layer_count[std::size_t(c)] = count;
    });
    std::vector<std::uint64_t> layer_first(std::size_t(n[2]) + 1, 0);
    for (std::size_t c = 0; c < layer_count.size(); ++c) layer_first[c + 1] = layer_first[c] + layer_count[c];
    if (layer_first.back() >= kNone) throw Error("label map: too many surface vertices for 32-bit indices");
    vertices.base.resize(std::size_t(layer_first.back()));
    vertices.corner.resize(std::size_t(layer_first.back()));
    tbb::parallel_for(std::int64_t(0), n[2], [&](std::int64_t c) {
        for (std::int64_t b = 0; b < n[1]; ++b)
            for (std::int64_t a = 0; a < n[0]; ++a) {
                std::uint32_t& f = first[grid.corner_index(a, b, c)];
                if (f == kNone) continue;
                f += std::uint32_t(layer_first[std::size_t(c)]);
                const CornerSheets s = grid.sheets(a, b, c);
                const Point corner{a - 0.5, b - 0.5, c - 0.5};
                std::vector<Point> toward(std::size_t(s.count), Point{0, 0, 0});
                std::vector<int> walls(std::size_t(s.count), 0);
                for (int face = 0; face < 12; ++face) {
                    if (s.sheet[face] < 0) continue;
                    const int axis = face >> 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
                    Point& t = toward[std::size_t(s.sheet[face])];
                    t[u] += (face & 1) ? 0.5 : -0.5;
                    t[v] += (face >> 1 & 1) ? 0.5 : -0.5;
                    ++walls[std::size_t(s.sheet[face])];
                }
                for (int k = 0; k < s.count; ++k) {
                    Point p = corner;
                    // Several sheets: each halfway toward the mean middle of its walls, so they part.
                    if (s.count > 1)
                        for (int i = 0; i < 3; ++i) p[i] += 0.5 * toward[std::size_t(k)][i] / walls[std::size_t(k)];
                    vertices.base[f + std::uint32_t(k)] = p;
                    vertices.corner[f + std::uint32_t(k)] = corner;
                }
            }
    });
}

/// One quad per wall, in a fixed order (z, y, x of its low voxel, then the axis); the corners
/// turn counter-clockwise seen from the high voxel, so the normal points from low to high.
void collect_quads(const LabelGrid& grid, const std::vector<std::uint32_t>& first, std::vector<SheetQuad>& quads) {
    const std::int64_t nz = grid.dims[2] + 1;
    std::vector<std::vector<SheetQuad>> per_layer(static_cast<std::size_t>(nz));
    tbb::parallel_for(std::int64_t(-1), grid.dims[2], [&](std::int64_t z) {
        std::vector<SheetQuad>& out = per_layer[std::size_t(z + 1)];
        for (std::int64_t y = -1; y < grid.dims[1]; ++y)
            for (std::int64_t x = -1; x < grid.dims[0]; ++x) {
                const std::array<std::int64_t, 3> p{x, y, z};
                const std::uint16_t low = grid.at(x, y, z);
                for (int axis = 0; axis < 3; ++axis) {
                    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                    if (p[u] < 0 || p[v] < 0 || p[u] >= grid.dims[u] || p[v] >= grid.dims[v]) continue;
                    std::array<std::int64_t, 3> q = p;
                    ++q[axis];
                    const std::uint16_t high = grid.at(q[0], q[1], q[2]);
                    if (low == high) continue;
                    SheetQuad quad;
                    quad.sides = {low, high};
                    const int steps[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                    for (int k = 0; k < 4; ++k) {
                        std::array<std::int64_t, 3> corner{};
                        corner[axis] = p[axis] + 1;
                        corner[u] = p[u] + steps[k][0];
                        corner[v] = p[v] + steps[k][1];
                        const CornerSheets s = grid.sheets(corner[0], corner[1], corner[2]);
                        const int face = 4 * axis + (1 - steps[k][0]) + 2 * (1 - steps[k][1]);
                        quad.vertex[k] = first[grid.corner_index(corner[0], corner[1], corner[2])] + std::uint32_t(s.sheet[face]);
                    }
                    out.push_back(quad);
                }
            }
    });
    for (const auto& layer : per_layer) quads.insert(quads.end(), layer.begin(), layer.end());
}

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace

LabelSurface mesh_labels(const LabelVolume& volume, const LabelMeshOptions& options,
                         const std::function<void(double)>& progress) {
    if (!(options.max_offset > 0 && options.max_offset <= 2))
        throw UsageError("label mesher: max offset: expected a distance in (0, 2] voxels, got " + std::to_string(options.max_offset));
    if (options.smoothing_iterations < 0)
        throw UsageError("--smooth-iterations: expected >= 0, got " + std::to_string(options.smoothing_iterations));
    LabelSurface surface;
    Clock::time_point start = Clock::now();
    LabelGrid grid = make_grid(volume, options, surface.labels);
    surface.relabelled_voxels = make_manifold(grid);
    surface.phases.emplace_back("manifold", seconds_since(start));
    if (progress) progress(0.2);

    start = Clock::now();
    std::vector<std::uint32_t> first;
    SheetVertices vertices;
    number_vertices(grid, first, vertices);
    std::vector<SheetQuad> quads;
    collect_quads(grid, first, quads);
    first = {};
    surface.phases.emplace_back("sheets", seconds_since(start));
    if (progress) progress(0.4);

    std::vector<std::uint64_t> voxels(std::size_t(kMaxLabel) + 1, 0);
    for (std::uint16_t label : grid.labels)
        if (label) ++voxels[label];
    smooth_sheets(vertices, quads, voxels, options, volume.header.index_to_world, surface, progress);
    return surface;
}

Mesh label_mesh(const LabelSurface& surface, std::uint32_t label) {
    Mesh mesh;
    std::vector<std::uint32_t> remap(surface.mesh.vertices.size(), kNone);
    const auto use = [&](std::uint32_t v) {
        if (remap[v] == kNone) remap[v] = std::uint32_t(mesh.vertices.size()), mesh.vertices.push_back(surface.mesh.vertices[v]);
        return remap[v];
    };
    for (std::size_t t = 0; t < surface.mesh.triangles.size(); ++t) {
        const auto& tri = surface.mesh.triangles[t];
        if (surface.sides[t][0] == label) mesh.triangles.push_back({use(tri[0]), use(tri[1]), use(tri[2])});
        else if (surface.sides[t][1] == label) mesh.triangles.push_back({use(tri[0]), use(tri[2]), use(tri[1])});
    }
    return mesh;
}

}  // namespace vdbmesh
