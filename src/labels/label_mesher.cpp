// mesh_labels(): the multi-label dual mesh (labels.h). One vertex per sheet of walls through a
// voxel corner (corner_sheets.h), one quad per pair of face-adjacent voxels with different
// labels, split into two triangles; vertices smoothed within their box round the corner
// (smooth_sheets.h), held back where a triangle would cross another.

#include <tbb/enumerable_thread_specific.h>
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

/// Per corner its first vertex (kNone: no wall there); per vertex its unsmoothed place (the
/// corner itself, or for several sheets each moved toward the middle of its walls) and, at a
/// corner's first vertex, the corner's sheet of each face (for collect_quads()).
void number_vertices(const LabelGrid& grid, std::vector<std::uint32_t>& first, SheetVertices& vertices,
                     std::vector<std::array<std::int8_t, 12>>& face_sheets) {
    const std::array<std::int64_t, 3> n = grid.corner_dims();
    first.assign(std::size_t(n[0] * n[1] * n[2]), kNone);
    struct Found {
        std::int64_t a, b;
        CornerSheets sheets;
    };
    std::vector<std::vector<Found>> layers(static_cast<std::size_t>(n[2]));
    tbb::parallel_for(std::int64_t(0), n[2], [&](std::int64_t c) {
        for (std::int64_t b = 0; b < n[1]; ++b)
            for (std::int64_t a = 0; a < n[0]; ++a) {
                if (grid.uniform(a, b, c)) continue;
                layers[std::size_t(c)].push_back({a, b, grid.sheets(a, b, c)});
            }
    });
    std::vector<std::uint64_t> layer_first(std::size_t(n[2]) + 1, 0);
    for (std::size_t c = 0; c < layers.size(); ++c) {
        layer_first[c + 1] = layer_first[c];
        for (const Found& f : layers[c]) layer_first[c + 1] += std::uint64_t(f.sheets.count);
    }
    if (layer_first.back() >= kNone) throw Error("label map: too many surface vertices for 32-bit indices");
    vertices.base.resize(std::size_t(layer_first.back()));
    vertices.corner.resize(std::size_t(layer_first.back()));
    face_sheets.resize(std::size_t(layer_first.back()));
    tbb::parallel_for(std::int64_t(0), n[2], [&](std::int64_t c) {
        std::uint32_t next = std::uint32_t(layer_first[std::size_t(c)]);
        for (const Found& found : layers[std::size_t(c)]) {
            const CornerSheets& s = found.sheets;
            const std::uint32_t f = first[grid.corner_index(found.a, found.b, c)] = next;
            next += std::uint32_t(s.count);
            face_sheets[f] = s.sheet;
            const Point corner{found.a - 0.5, found.b - 0.5, c - 0.5};
            std::array<Point, 12> toward{};  // per sheet (at most one per face)
            std::array<int, 12> walls{};
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

/// Whether voxel (x, y, z) is inside the map with its next voxel along each axis, all four the same.
bool same_as_next(const LabelGrid& grid, std::int64_t x, std::int64_t y, std::int64_t z) {
    if (x < 0 || y < 0 || z < 0 || x + 1 >= grid.dims[0] || y + 1 >= grid.dims[1] || z + 1 >= grid.dims[2]) return false;
    const std::size_t row = std::size_t(grid.dims[0]), slice = row * std::size_t(grid.dims[1]);
    const std::uint16_t* p = grid.labels.data() + std::size_t((z * grid.dims[1] + y) * grid.dims[0] + x);
    return p[0] == p[1] && p[0] == p[row] && p[0] == p[slice];
}

/// One quad per wall, in a fixed order (z, y, x of its low voxel, then the axis); the corners
/// turn counter-clockwise seen from the high voxel, so the normal points from low to high.
void collect_quads(const LabelGrid& grid, const std::vector<std::uint32_t>& first,
                   const std::vector<std::array<std::int8_t, 12>>& face_sheets, std::vector<SheetQuad>& quads) {
    const std::int64_t nz = grid.dims[2] + 1;
    std::vector<std::vector<SheetQuad>> per_layer(static_cast<std::size_t>(nz));
    tbb::parallel_for(std::int64_t(-1), grid.dims[2], [&](std::int64_t z) {
        std::vector<SheetQuad>& out = per_layer[std::size_t(z + 1)];
        for (std::int64_t y = -1; y < grid.dims[1]; ++y)
            for (std::int64_t x = -1; x < grid.dims[0]; ++x) {
                if (same_as_next(grid, x, y, z)) continue;  // most voxels: no wall
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
                        const int face = 4 * axis + (1 - steps[k][0]) + 2 * (1 - steps[k][1]);
                        const std::uint32_t f = first[grid.corner_index(corner[0], corner[1], corner[2])];
                        quad.vertex[k] = f + std::uint32_t(face_sheets[f][face]);
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
    std::vector<std::array<std::int8_t, 12>> face_sheets;
    number_vertices(grid, first, vertices, face_sheets);
    std::vector<SheetQuad> quads;
    collect_quads(grid, first, face_sheets, quads);
    first = {};
    face_sheets = {};
    surface.phases.emplace_back("sheets", seconds_since(start));
    if (progress) progress(0.4);

    std::vector<std::uint64_t> voxels(std::size_t(kMaxLabel) + 1, 0);
    for (std::uint16_t label : grid.labels)
        if (label) ++voxels[label];
    smooth_sheets(vertices, quads, voxels, options, volume.header.index_to_world, surface, progress);
    return surface;
}

namespace {

/// The mesh of @a label from its triangles of @a surface (ascending); @a remap: per vertex of
/// the surface kNone, and so again on return.
Mesh mesh_of_label(const LabelSurface& surface, std::uint32_t label, const std::vector<std::uint32_t>& triangles,
                   std::vector<std::uint32_t>& remap) {
    Mesh mesh;
    const auto use = [&](std::uint32_t v) {
        if (remap[v] == kNone) remap[v] = std::uint32_t(mesh.vertices.size()), mesh.vertices.push_back(surface.mesh.vertices[v]);
        return remap[v];
    };
    mesh.triangles.reserve(triangles.size());
    for (std::uint32_t t : triangles) {
        const auto& tri = surface.mesh.triangles[t];
        if (surface.sides[t][0] == label) mesh.triangles.push_back({use(tri[0]), use(tri[1]), use(tri[2])});
        else mesh.triangles.push_back({use(tri[0]), use(tri[2]), use(tri[1])});
    }
    for (std::uint32_t t : triangles)
        for (std::uint32_t v : surface.mesh.triangles[t]) remap[v] = kNone;
    return mesh;
}

}  // namespace

Mesh label_mesh(const LabelSurface& surface, std::uint32_t label) {
    std::vector<std::uint32_t> triangles;
    for (std::uint32_t t = 0; t < surface.mesh.triangles.size(); ++t)
        if (surface.sides[t][0] == label || surface.sides[t][1] == label) triangles.push_back(t);
    std::vector<std::uint32_t> remap(surface.mesh.vertices.size(), kNone);
    return mesh_of_label(surface, label, triangles, remap);
}

std::vector<Mesh> label_meshes(const LabelSurface& surface) {
    std::vector<std::int32_t> slot(std::size_t(kMaxLabel) + 1, -1);
    for (std::size_t i = 0; i < surface.labels.size(); ++i) slot[surface.labels[i]] = std::int32_t(i);
    std::vector<std::vector<std::uint32_t>> triangles(surface.labels.size());
    for (std::uint32_t t = 0; t < surface.mesh.triangles.size(); ++t)
        for (std::uint16_t label : surface.sides[t])
            if (slot[label] >= 0) triangles[std::size_t(slot[label])].push_back(t);
    std::vector<Mesh> meshes(surface.labels.size());
    tbb::enumerable_thread_specific<std::vector<std::uint32_t>> remaps(std::vector<std::uint32_t>(surface.mesh.vertices.size(), kNone));
    tbb::parallel_for(std::size_t(0), meshes.size(), [&](std::size_t i) {
        meshes[i] = mesh_of_label(surface, surface.labels[i], triangles[i], remaps.local());
    });
    return meshes;
}

}  // namespace vdbmesh
