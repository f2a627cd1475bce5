// Intersection-free octree contouring, the driver: per block in parallel, the octree; per
// lower internal node in parallel, the cells across blocks; per block, the triangles with
// keyed vertices, grouped by node; then one weld of the keys (dc_weld.cpp). Blocks and nodes
// are visited in a fixed order and every vertex list has a fixed order, so the mesh does not
// depend on the thread count, nor on bricks (dc_bricks.cpp; docs/dmc.md, "Bricks").

#include "mesh/dual_contouring.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <algorithm>
#include <array>
#include <memory>

#include "mesh/dc_polygons.h"
#include "mesh/mesh_phases.h"
#include "mesh/surface_blocks.h"

namespace vdbmesh::detail {

namespace {

/// Gives the pages of freed small allocations (the blocks' cells, 1.2 KB each, spread over the
/// threads' heaps) back to the system before the weld allocates its large arrays; else they
/// stay resident under them and raise the peak (bunny at --error 0.25: 194 MB without, 172 MB
/// with, against volumeToMesh's 178 MB). It costs about 40 ms there, and 0.7 ms, a serial
/// 1.5% of the whole, on the walnut, whose cells (10 MB) do not matter: so only above
/// kTrimAboveBytes of cells.
constexpr std::size_t kTrimAboveBytes = std::size_t(32) << 20;

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

/// Whether block @a n (IfcCellGrid::neighbours(); -1: none) is one cell of 8 voxels or more,
/// as the coarse merge left it (a block split since was one).
bool one_large_cell(const IfcCellGrid& cells, std::ptrdiff_t n) {
    if (n < 0 || !cells.blocks[std::size_t(n)]) return false;
    const IfcBlockCells& block = *cells.blocks[std::size_t(n)];
    return block.was_split || (block.cells.size() == 1 && block.cells[0].level >= kIfcMaxLevel);
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

}  // namespace

void release_free_memory() {
#ifdef __GLIBC__
    malloc_trim(0);
#endif
}

void split_clipped_blocks(IfcCellGrid& cells, const IfcOriginFilter& decide) {
    std::vector<char> chosen(cells.blocks.size(), 0), split(cells.blocks.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.blocks.size()), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            const IfcBlockCells* block = cells.blocks[b].get();
            if (!block || block->split_decided || (decide && !decide(cells.origins[b]))) continue;
            chosen[b] = 1;
            split[b] = clipped_next_to_smaller_cells(cells, b);
        }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.blocks.size()), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            if (!chosen[b]) continue;
            IfcBlockCells& block = *cells.blocks[b];
            if (split[b]) {
                static_cast<IfcLeaves&>(block) = std::move(static_cast<IfcLeaves&>(*block.parts));
                block.root_leaf = false;
                block.was_split = true;
            }
            block.parts.reset();
            block.split_decided = true;
        }
    });
}

std::vector<IfcNodeOutput> group_ifc_outputs_by_node(const std::vector<openvdb::Coord>& origins, std::vector<IfcBlockOutput>& outputs) {
    std::vector<IfcNodeOutput> nodes;
    std::vector<std::vector<std::size_t>> members;
    std::vector<std::pair<openvdb::Coord, std::size_t>> by_node;  // node origin, block
    for (std::size_t b = 0; b < origins.size(); ++b) {
        if (outputs[b].vertices.empty() && outputs[b].triangles.empty()) continue;
        const openvdb::Coord& o = origins[b];
        by_node.push_back({ifc_node_of(o), b});
    }
    // Stable: the blocks of a node keep their origin order.
    std::stable_sort(by_node.begin(), by_node.end(), [](const auto& a, const auto& b) { return ifc_node_before(a.first, b.first); });
    for (std::size_t i = 0; i < by_node.size(); ++i) {
        if (i == 0 || by_node[i].first != by_node[i - 1].first) {
            nodes.push_back({by_node[i].first, {}, {}});
            members.emplace_back();
        }
        members.back().push_back(by_node[i].second);
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes.size()), [&](const auto& range) {
        for (std::size_t n = range.begin(); n != range.end(); ++n) {
            IfcNodeOutput& node = nodes[n];
            for (const std::size_t b : members[n]) {
                std::vector<IfcVertex>& listed = outputs[b].vertices;
                for (const IfcVertex& v : listed) {
                    if (ifc_key_of_coarse_cell(v.key)) node.coarse.push_back(v);
                }
                listed.erase(std::remove_if(listed.begin(), listed.end(), [](const IfcVertex& v) { return ifc_key_of_coarse_cell(v.key); }),
                             listed.end());
                node.blocks.push_back(std::move(outputs[b]));
            }
            auto by_key = [](const IfcVertex& a, const IfcVertex& b) { return a.key < b.key; };
            std::sort(node.coarse.begin(), node.coarse.end(), by_key);
            node.coarse.erase(std::unique(node.coarse.begin(), node.coarse.end(), [](const IfcVertex& a, const IfcVertex& b) { return a.key == b.key; }),
                              node.coarse.end());
        }
    });
    return nodes;
}

IfcCellGrid build_ifc_cell_grid(const openvdb::FloatGrid& grid, const SampleClassifier& classifier, const MeshOptions& options,
                                const std::optional<openvdb::CoordBBox>& within, MeshReport& report, const IfcOriginFilter& build_node) {
    PhaseClock clock;
    IfcCellGrid cells;
    cells.origins = surface_blocks(grid, classifier, within);
    if (build_node) {
        cells.origins.erase(std::remove_if(cells.origins.begin(), cells.origins.end(),
                                           [&](const openvdb::Coord& o) { return !build_node(ifc_node_of(o)); }),
                            cells.origins.end());
    }
    cells.blocks.resize(cells.origins.size());
    auto may_hold_surface = [&](std::size_t b, auto& accessor) { return block_may_hold_surface(accessor, classifier, cells.origins[b]); };
    for_each_surface_block(grid, classifier, cells.origins, may_hold_surface, [&](const IfcSamples& samples, std::size_t b) {
        build_ifc_cells(samples, options.iso, options.error, options.sharp, cells.block_for_writing(b));
    });
    clock.lap(report, "octree");
    merge_ifc_coarse_cells(grid, classifier, options.error, cells);
    clock.lap(report, "coarse");
    return cells;
}

std::vector<IfcBlockOutput> contour_ifc_cells(const openvdb::FloatGrid& grid, const SampleClassifier& classifier, const MeshOptions& options,
                                              const IfcCellGrid& cells, const IfcOriginFilter& own, MeshReport& report) {
    PhaseClock clock;
    std::vector<IfcBlockOutput> outputs(cells.origins.size());
    // Only the blocks the octree sampled hold surface of their own; their samples are not
    // loaded again (build_ifc_cells() kept what the contour reads).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.origins.size()), [&](const auto& range) {
        auto accessor = grid.getConstAccessor();
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            if (!cells.blocks[b] || !cells.blocks[b]->sampled || (own && !own(cells.origins[b]))) continue;
            contour_ifc_block(classifier, accessor, cells, b, options.error, grid.transform(), outputs[b]);
            outputs[b].vertices.shrink_to_fit();  // growth leaves up to half unused: it adds up over blocks
            outputs[b].triangles.shrink_to_fit();
        }
    });
    clock.lap(report, "contour");
    return outputs;
}

std::vector<IfcNodeOutput> contour_ifc_nodes(const openvdb::FloatGrid& grid, const SampleClassifier& classifier, const MeshOptions& options,
                                             MeshReport& report) {
    IfcCellGrid cells = build_ifc_cell_grid(grid, classifier, options, std::nullopt, report);
    PhaseClock clock;
    split_clipped_blocks(cells, {});
    clock.lap(report, "split");
    if (options.progress) options.progress(0.4);
    std::vector<IfcBlockOutput> outputs = contour_ifc_cells(grid, classifier, options, cells, {}, report);
    if (options.progress) options.progress(0.8);
    // Not needed by the weld; the blocks' cells (one allocation each) are freed in parallel.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.blocks.size()), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) cells.blocks[b].reset();
    });
    const bool trim = cells.blocks.size() * sizeof(IfcBlockCells) > kTrimAboveBytes;
    cells.blocks.clear();
    cells.blocks.shrink_to_fit();
    if (trim) release_free_memory();
    std::vector<IfcNodeOutput> nodes = group_ifc_outputs_by_node(cells.origins, outputs);
    clock.lap(report, "weld");
    return nodes;
}

Mesh intersection_free_contouring(const openvdb::FloatGrid& grid, const MeshOptions& options, MeshReport& report) {
    const SampleClassifier classifier(grid, options);
    std::vector<IfcNodeOutput> nodes = contour_ifc_nodes(grid, classifier, options, report);
    PhaseClock clock;
    Mesh mesh = weld_ifc_nodes(std::move(nodes));
    clock.lap(report, "weld");
    if (options.progress) options.progress(1.0);
    return mesh;
}

}  // namespace vdbmesh::detail
