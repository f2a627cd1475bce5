// Intersection-free octree contouring, the driver: per block in parallel, the octree; per
// lower internal node in parallel, the cells across blocks; per block, the triangles with
// keyed vertices; then one weld of the keys. Blocks and nodes are visited in a fixed order
// and every vertex list has a fixed order, so the mesh does not depend on the thread count.

#include "mesh/ifc.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <algorithm>
#include <array>
#include <memory>

#include "vdbmesh/huge_pages.h"
#include "mesh/ifc_key_index.h"
#include "mesh/ifc_polygons.h"
#include "mesh/mesh_phases.h"
#include "mesh/surface_blocks.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

/// Gives the pages of freed small allocations (the blocks' cells, 1.2 KB each, spread over the
/// threads' heaps) back to the system before the weld allocates its large arrays; else they
/// stay resident under them and raise the peak (bunny at --error 0.25: 194 MB without, 172 MB
/// with, against volumeToMesh's 178 MB). It costs about 40 ms there, and 0.7 ms, a serial
/// 1.5% of the whole, on the walnut, whose cells (10 MB) do not matter: so only above
/// kTrimAboveBytes of cells.
constexpr std::size_t kTrimAboveBytes = std::size_t(32) << 20;
void release_free_memory() {
#ifdef __GLIBC__
    malloc_trim(0);
#endif
}

/// Calls @a visit(samples, block) for every block holding surface among those
/// @a may_hold_surface(block, accessor) accepts, in parallel.
template <typename Candidate, typename Visit>
void for_each_surface_block(const openvdb::FloatGrid& grid, const SampleClassifier& classifier,
                            const std::vector<openvdb::Coord>& origins, Candidate&& may_hold_surface, Visit&& visit) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, origins.size()), [&](const auto& range) {
        auto accessor = grid.getConstAccessor();
        auto samples = std::make_unique<IfcSamples>();
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            if (!may_hold_surface(b, accessor)) continue;
            samples->origin = origins[b];
            load_ifc_samples(accessor, classifier, *samples);
            if (!samples->uniform()) visit(*samples, b);
        }
    });
}

/// Whether block @a n (IfcCellGrid::neighbours(); -1: none) is one cell of 8 voxels or more.
bool one_large_cell(const IfcCellGrid& cells, std::ptrdiff_t n) {
    if (n < 0 || !cells.blocks[std::size_t(n)]) return false;
    const IfcBlockCells& block = *cells.blocks[std::size_t(n)];
    return block.cells.size() == 1 && block.cells[0].level >= kIfcMaxLevel;
}

/// Whether block @a b, one 8-voxel cell of its own, has a face its surface only clips
/// (IfcBlockCells::Parts::clipped_faces) with no cell as large across it.
bool clipped_next_to_smaller_cells(const IfcCellGrid& cells, std::size_t b) {
    const IfcBlockCells& block = *cells.blocks[b];
    if (!block.parts || block.cells.size() != 1 || block.cells[0].level != kIfcMaxLevel) return false;
    const std::array<std::ptrdiff_t, 27> around = cells.neighbours(b);
    for (int face = 0; face < 6; ++face) {
        if (!((block.parts->clipped_faces >> face) & 1u)) continue;
        std::array<int, 3> offset{};
        offset[face / 2] = face & 1 ? 1 : -1;
        if (!one_large_cell(cells, around[IfcCellGrid::neighbour_slot(offset[0], offset[1], offset[2])])) return true;
    }
    return false;
}

/// Splits the blocks that are still one 8-voxel cell of their own after the merge across
/// blocks, whose surface only clips one of their faces, where the block across that face is not
/// one cell as large: their cells become the ones the octree kept for that
/// (IfcBlockCells::Parts). The triangles over the clipped face would join the cell's vertex,
/// about 4 voxels away, to a chord or to segments under a voxel or two long. Next to a cell as
/// large, or inside a coarse cell, a block stays whole: splitting there too cost the sphere of
/// DcTest 32% more triangles. Decided from the cells after the coarse merge, then applied, so in
/// any order. Engine at --error 0.5 / 1, angles under 10 degrees: 0.64% / 0.63% -> 0.49% / 0.45%,
/// triangles +0.2% / +1.9% (docs/dmc.md, "Session 12").
void split_clipped_blocks(IfcCellGrid& cells) {
    std::vector<char> split(cells.blocks.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.blocks.size()), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) split[b] = cells.blocks[b] && clipped_next_to_smaller_cells(cells, b);
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.blocks.size()), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            IfcBlockCells* block = cells.blocks[b].get();
            if (!block || !block->parts) continue;
            if (split[b]) {
                static_cast<IfcLeaves&>(*block) = std::move(static_cast<IfcLeaves&>(*block->parts));
                block->root_leaf = false;
            }
            block->parts.reset();
        }
    });
}

/// The blocks' vertices, each key once, as keys and positions apart (the positions become the
/// mesh's): block after block, then the cells larger than a block in key order. A block lists
/// each of its keys once, and only those cells are listed by several blocks
/// (ifc_key_of_coarse_cell()), so no global sort is needed. Each block's list is released once
/// copied.
struct GatheredVertices {
    std::vector<std::uint64_t> keys;
    std::vector<std::array<float, 3>> positions;
};

GatheredVertices gather_vertices(std::vector<IfcBlockOutput>& outputs) {
    std::vector<std::size_t> first_own(outputs.size() + 1, 0), first_coarse(outputs.size() + 1, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, outputs.size()), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            const auto& listed = outputs[b].vertices;
            first_coarse[b + 1] = std::size_t(std::count_if(listed.begin(), listed.end(), [](const IfcVertex& v) { return ifc_key_of_coarse_cell(v.key); }));
            first_own[b + 1] = listed.size() - first_coarse[b + 1];
        }
    });
    for (std::size_t b = 0; b < outputs.size(); ++b) {
        first_own[b + 1] += first_own[b];
        first_coarse[b + 1] += first_coarse[b];
    }
    const std::size_t own_count = first_own.back();
    GatheredVertices gathered;
    reserve_on_huge_pages(gathered.keys, own_count + first_coarse.back());
    gathered.keys.resize(own_count);
    reserve_on_huge_pages(gathered.positions, own_count + first_coarse.back());
    gathered.positions.resize(own_count);
    std::vector<IfcVertex> coarse(first_coarse.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, outputs.size()), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            std::size_t own = first_own[b], next_coarse = first_coarse[b];
            for (const IfcVertex& v : outputs[b].vertices) {
                if (ifc_key_of_coarse_cell(v.key)) {
                    coarse[next_coarse++] = v;
                } else {
                    gathered.keys[own] = v.key;
                    gathered.positions[own++] = v.position;
                }
            }
            outputs[b].vertices = {};
        }
    });
    std::sort(coarse.begin(), coarse.end(), [](const IfcVertex& a, const IfcVertex& b) { return a.key < b.key; });
    coarse.erase(std::unique(coarse.begin(), coarse.end(), [](const IfcVertex& a, const IfcVertex& b) { return a.key == b.key; }), coarse.end());
    for (const IfcVertex& v : coarse) {
        gathered.keys.push_back(v.key);
        gathered.positions.push_back(v.position);
    }
    return gathered;
}

/// One vertex per key, numbered as gather_vertices() lists them; vertices no triangle uses are
/// dropped. Each block's output is released once read, so no part of it is held twice.
Mesh weld(std::vector<IfcBlockOutput>&& outputs) {
    std::vector<std::size_t> first_triangle(outputs.size() + 1, 0);
    for (std::size_t b = 0; b < outputs.size(); ++b) first_triangle[b + 1] = first_triangle[b] + outputs[b].triangles.size();
    GatheredVertices vertices = gather_vertices(outputs);
    const std::size_t vertex_count = vertices.keys.size();
    if (vertex_count >= IfcKeyIndex::kMissing) throw Error("contouring: more than 2^32 vertices");
    const IfcKeyIndex index_of(vertices.keys);
    vertices.keys = {};
    Mesh mesh;
    reserve_on_huge_pages(mesh.triangles, first_triangle.back());
    mesh.triangles.resize(first_triangle.back());
    std::vector<std::uint8_t> used;
    reserve_on_huge_pages(used, vertex_count);
    used.resize(vertex_count, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, outputs.size()), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            auto& keyed = outputs[b].triangles;
            constexpr std::size_t kAhead = 8;  // triangles: about the latency of a miss
            for (std::size_t t = 0; t < std::min(kAhead, keyed.size()); ++t) {
                for (const std::uint64_t key : keyed[t]) index_of.prefetch(key);
            }
            for (std::size_t t = 0; t < keyed.size(); ++t) {
                if (t + kAhead < keyed.size()) {
                    for (const std::uint64_t key : keyed[t + kAhead]) index_of.prefetch(key);
                }
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t index = index_of.find(keyed[t][k]);
                    if (index == IfcKeyIndex::kMissing) throw Error("contouring: a triangle refers to a missing vertex");
                    mesh.triangles[first_triangle[b] + t][k] = index;
                    used[index] = 1;  // every writer writes 1: no race on the value
                }
            }
            keyed = {};
        }
    });
    const std::size_t used_count = std::size_t(std::count(used.begin(), used.end(), std::uint8_t(1)));
    if (used_count == vertex_count) {  // as on every scan measured: no renumbering
        mesh.vertices = std::move(vertices.positions);
        return mesh;
    }
    reserve_on_huge_pages(mesh.vertices, used_count);
    std::vector<std::uint32_t> new_index;
    reserve_on_huge_pages(new_index, vertex_count);
    new_index.resize(vertex_count);
    for (std::size_t v = 0; v < vertex_count; ++v) {
        new_index[v] = std::uint32_t(mesh.vertices.size());
        if (used[v]) mesh.vertices.push_back(vertices.positions[v]);
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangles.size()), [&](const auto& range) {
        for (std::size_t t = range.begin(); t != range.end(); ++t) {
            for (auto& v : mesh.triangles[t]) v = new_index[v];
        }
    });
    return mesh;
}

}  // namespace

Mesh intersection_free_contouring(const openvdb::FloatGrid& grid, const MeshOptions& options, MeshReport& report) {
    PhaseClock clock;
    const SampleClassifier classifier(grid, options);
    IfcCellGrid cells;
    cells.origins = surface_blocks(grid, classifier);
    cells.blocks.resize(cells.origins.size());
    auto may_hold_surface = [&](std::size_t b, auto& accessor) { return block_may_hold_surface(accessor, classifier, cells.origins[b]); };
    for_each_surface_block(grid, classifier, cells.origins, may_hold_surface, [&](const IfcSamples& samples, std::size_t b) {
        build_ifc_cells(samples, options.iso, options.error, cells.block_for_writing(b));
    });
    clock.lap(report, "octree");
    merge_ifc_coarse_cells(grid, classifier, options.error, cells);
    clock.lap(report, "coarse");
    split_clipped_blocks(cells);
    clock.lap(report, "split");
    if (options.progress) options.progress(0.4);
    std::vector<IfcBlockOutput> outputs(cells.origins.size());
    // Only the blocks the octree sampled hold surface of their own; their samples are not
    // loaded again (build_ifc_cells() kept what the contour reads).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.origins.size()), [&](const auto& range) {
        auto accessor = grid.getConstAccessor();
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            if (!cells.blocks[b] || !cells.blocks[b]->sampled) continue;
            contour_ifc_block(classifier, accessor, cells, b, options.error, grid.transform(), outputs[b]);
            outputs[b].vertices.shrink_to_fit();  // growth leaves up to half unused: it adds up over blocks
            outputs[b].triangles.shrink_to_fit();
        }
    });
    clock.lap(report, "contour");
    if (options.progress) options.progress(0.8);
    // Not needed by the weld; the blocks' cells (one allocation each) are freed in parallel.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.blocks.size()), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) cells.blocks[b].reset();
    });
    const bool trim = cells.blocks.size() * sizeof(IfcBlockCells) > kTrimAboveBytes;
    cells = IfcCellGrid();
    if (trim) release_free_memory();
    Mesh mesh = weld(std::move(outputs));
    clock.lap(report, "weld");
    if (options.progress) options.progress(1.0);
    return mesh;
}

}  // namespace vdbmesh::detail
