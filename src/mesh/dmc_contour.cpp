// Marching Cubes on the dual cells (Schaefer and Warren, "Dual Marching Cubes: Primal
// Contouring of Dual Grids", 2004, section 4) with the shared table of mc_table.h, and exact,
// deterministic welding without coordinate hashing.
//
// A mesh vertex lies on a dual edge: two octree cells A (low) and B (high) adjacent along an
// axis. Its key is the canonical voxel v of that face contact (v[axis] = B.min[axis] - 1, on
// the other axes the larger of the two minima) with the axis: A holds v and B holds v + axis,
// so the key names the pair uniquely. The vertex belongs to the leaf holding v (or, in a tile,
// the leaf holding v + axis), as a bit in that leaf's slot mask (local coordinates in [-1, 8],
// 3 axes). Passes: (1) per leaf, in parallel, contour its dual cells into triangles of vertex
// references and set the referenced bits (atomic OR: order-free); (2) count bits per leaf,
// prefix-sum, and place each vertex; (3) turn references into indices by rank. Output order
// depends only on the tree, never on the thread count.

#include "mesh/dmc_contour.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bitset>
#include <memory>

#include "mesh/dmc_dual_cells.h"
#include "mesh/edge_crossing.h"
#include "mesh/mc_table.h"

namespace vdbmesh::detail {

namespace {

constexpr int kSlotDim = kLeafDim + 2;                // local coordinates -1 .. 8
constexpr int kSlotsPerAxis = kSlotDim * kSlotDim * kSlotDim;
constexpr int kSlots = 3 * kSlotsPerAxis;
constexpr int kWords = (kSlots + 63) / 64;
constexpr int kSlotBits = 12;                         // kSlots < 2^12

/// A vertex as seen from one leaf: the owner's neighbour_slot << kSlotBits | slot in the owner.
using VertexRef = DmcVertexRef;

int slot_of(int axis, const openvdb::Coord& local) {
    return axis * kSlotsPerAxis + ((local.x() + 1) * kSlotDim + (local.y() + 1)) * kSlotDim + (local.z() + 1);
}

struct SlotEdge {
    int axis;
    int x, y, z;
};
SlotEdge edge_of_slot(int slot) {
    const int axis = slot / kSlotsPerAxis;
    const int rest = slot % kSlotsPerAxis;
    return {axis, rest / (kSlotDim * kSlotDim) - 1, (rest / kSlotDim) % kSlotDim - 1, rest % kSlotDim - 1};
}

/// Per leaf, the slots of the vertices it owns.
class VertexMarks {
public:
    explicit VertexMarks(std::size_t leaves) : words_(new std::atomic<std::uint64_t>[leaves * kWords]) {
        for (std::size_t i = 0; i < leaves * kWords; ++i) words_[i].store(0, std::memory_order_relaxed);
    }
    void mark(std::size_t leaf, unsigned slot) {
        words_[leaf * kWords + slot / 64].fetch_or(std::uint64_t(1) << (slot % 64), std::memory_order_relaxed);
    }
    std::uint64_t word(std::size_t leaf, int w) const { return words_[leaf * kWords + w].load(std::memory_order_relaxed); }

private:
    std::unique_ptr<std::atomic<std::uint64_t>[]> words_;
};

/// The vertex on the dual edge from corner @a a to corner @a b (b above a along @a axis).
VertexRef edge_vertex(const DmcGrid& grid, std::size_t leaf, const DualCorner& a, const DualCorner& b, int axis) {
    openvdb::Coord v;
    for (int k = 0; k < 3; ++k) v[k] = k == axis ? b.min[k] - 1 : std::max(a.min[k], b.min[k]);
    const openvdb::Coord origin = grid.leaves[leaf]->origin();
    const openvdb::Coord local = v - origin;
    int owner = neighbour_slot(block_offset(local.x()), block_offset(local.y()), block_offset(local.z()));
    if (grid.neighbours[leaf][std::size_t(owner)] < 0) {
        openvdb::Coord above = local;
        above[axis] += 1;
        owner = neighbour_slot(block_offset(above.x()), block_offset(above.y()), block_offset(above.z()));
    }
    // Both ends in tiles: a sign change between two tiles next to this leaf; it keeps the vertex.
    if (grid.neighbours[leaf][std::size_t(owner)] < 0) owner = neighbour_slot(0, 0, 0);
    const openvdb::Coord owner_origin(kLeafDim * (owner % 3 - 1), kLeafDim * (owner / 3 % 3 - 1), kLeafDim * (owner / 9 - 1));
    return (VertexRef(owner) << kSlotBits) | VertexRef(slot_of(axis, local - owner_origin));
}

std::size_t owner_leaf(const DmcGrid& grid, std::size_t leaf, VertexRef ref) {
    return std::size_t(grid.neighbours[leaf][ref >> kSlotBits]);
}
unsigned owner_slot(VertexRef ref) { return ref & ((1u << kSlotBits) - 1); }

using LeafTriangles = DmcLeafTriangles;

void contour_leaf(const DmcGrid& grid, const std::vector<LeafOctree>& octrees, std::size_t leaf, bool with_sources,
                  SampleBlock& block, std::vector<DualCell>& cells, VertexMarks& marks, LeafTriangles& out) {
    cells.clear();
    out = LeafTriangles();
    load_sample_block(grid, leaf, block);
    collect_dual_cells(grid, octrees, leaf, block, cells);
    out.triangles.reserve(2 * cells.size());
    for (const DualCell& cell : cells) {
        const McCase& mc = mc_case(cell.config);
        for (int t = 0; t < mc.triangle_count; ++t) {
            std::array<VertexRef, 3> triangle;
            for (int k = 0; k < 3; ++k) {
                const int edge = mc.triangles[std::size_t(t)][std::size_t(k)];
                const int c0 = kEdgeCorners[std::size_t(edge)][0], c1 = kEdgeCorners[std::size_t(edge)][1];
                const int axis = (c0 ^ c1) == 1 ? 0 : ((c0 ^ c1) == 2 ? 1 : 2);
                triangle[std::size_t(k)] = edge_vertex(grid, leaf, cell.corners[std::size_t(c0)], cell.corners[std::size_t(c1)], axis);
            }
            if (triangle[0] == triangle[1] || triangle[1] == triangle[2] || triangle[0] == triangle[2]) continue;
            for (VertexRef ref : triangle) marks.mark(owner_leaf(grid, leaf, ref), owner_slot(ref));
            out.triangles.push_back(triangle);
            if (with_sources) {
                const bool merged = std::any_of(cell.corners.begin(), cell.corners.end(),
                                                [](const DualCorner& corner) { return corner.size > 1; });
                out.sources.push_back({cell.p, merged});
            }
        }
    }
}

/// Rank tables: per leaf, the first global vertex index of each mark word.
std::vector<std::uint32_t> word_offsets(const VertexMarks& marks, std::size_t leaves) {
    std::vector<std::uint32_t> offsets(leaves * kWords + 1);
    std::uint64_t total = 0;
    for (std::size_t leaf = 0; leaf < leaves; ++leaf) {
        for (int w = 0; w < kWords; ++w) {
            offsets[leaf * kWords + std::size_t(w)] = std::uint32_t(total);
            total += std::bitset<64>(marks.word(leaf, w)).count();
        }
    }
    offsets.back() = std::uint32_t(total);
    return offsets;
}

void place_vertices(const DmcGrid& grid, const std::vector<LeafOctree>& octrees, const VertexMarks& marks,
                    const std::vector<std::uint32_t>& offsets, Mesh& mesh) {
    const openvdb::math::Transform& transform = grid.grid->transform();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid.leaves.size()), [&](const auto& range) {
        auto block = std::make_unique<SampleBlock>();
        for (std::size_t leaf = range.begin(); leaf != range.end(); ++leaf) {
            if (offsets[leaf * kWords] == offsets[(leaf + 1) * kWords]) continue;
            // Where no cell around is merged, both ends of an edge are samples: read just those.
            const bool plain = !neighbourhood_has_merges(grid, octrees, leaf);
            if (!plain) load_sample_block(grid, leaf, *block);
            const auto end = [&](int x, int y, int z) {
                if (!plain) return dual_corner(grid, octrees, leaf, *block, x, y, z);
                DualCorner sample;
                const openvdb::Coord voxel = grid.leaves[leaf]->origin().offsetBy(x, y, z);
                sample.position = {double(voxel.x()), double(voxel.y()), double(voxel.z())};
                sample.value = sample_value(grid, leaf, x, y, z);
                return sample;
            };
            std::uint32_t index = offsets[leaf * kWords];
            for (int w = 0; w < kWords; ++w) {
                for (std::uint64_t bits = marks.word(leaf, w); bits != 0; bits &= bits - 1) {
                    const SlotEdge e = edge_of_slot(w * 64 + __builtin_ctzll(bits));
                    const DualCorner a = end(e.x, e.y, e.z);
                    const DualCorner b = end(e.x + (e.axis == 0), e.y + (e.axis == 1), e.z + (e.axis == 2));
                    const Point3d p = edge_crossing(a.position, a.value, b.position, b.value, grid.iso);
                    const openvdb::Vec3d world = transform.indexToWorld(openvdb::Vec3d(p[0], p[1], p[2]));
                    mesh.vertices[index++] = {float(world[0]), float(world[1]), float(world[2])};
                }
            }
        }
    });
}

std::uint32_t vertex_index(const VertexMarks& marks, const std::vector<std::uint32_t>& offsets, std::size_t leaf,
                           unsigned slot) {
    const std::uint64_t below = marks.word(leaf, int(slot / 64)) & ((std::uint64_t(1) << (slot % 64)) - 1);
    return offsets[leaf * kWords + slot / 64] + std::uint32_t(std::bitset<64>(below).count());
}

/// Whether leaf @a leaf's triangles in @a cache still hold: no neighbour's octree changed.
bool reusable(const DmcGrid& grid, const DmcContourCache* cache, std::size_t leaf) {
    if (!cache || cache->per_leaf.size() != grid.leaves.size()) return false;
    return !grid.any_neighbour(leaf, [&](std::size_t n) { return cache->changed[n]; });
}

}  // namespace

DmcContour contour_dual_cells(const DmcGrid& grid, const std::vector<LeafOctree>& octrees, bool with_sources,
                              const std::function<void(double)>& progress, DmcContourCache* cache) {
    const std::size_t leaves = grid.leaves.size();
    VertexMarks marks(leaves);
    std::vector<LeafTriangles> fresh;
    if (cache && cache->per_leaf.size() == leaves && cache->changed.size() != leaves) cache->changed.assign(leaves, 0);
    std::vector<LeafTriangles>& per_leaf = cache ? cache->per_leaf : fresh;
    const bool had_cache = per_leaf.size() == leaves;
    if (!had_cache) per_leaf.assign(leaves, LeafTriangles());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves), [&](const auto& range) {
        auto block = std::make_unique<SampleBlock>();
        std::vector<DualCell> cells;
        for (std::size_t leaf = range.begin(); leaf != range.end(); ++leaf) {
            if (had_cache && reusable(grid, cache, leaf)) {
                for (const auto& triangle : per_leaf[leaf].triangles) {
                    for (VertexRef ref : triangle) marks.mark(owner_leaf(grid, leaf, ref), owner_slot(ref));
                }
                continue;
            }
            contour_leaf(grid, octrees, leaf, with_sources, *block, cells, marks, per_leaf[leaf]);
        }
    });
    if (cache) cache->changed.assign(leaves, 0);
    if (progress) progress(0.5);

    const std::vector<std::uint32_t> offsets = word_offsets(marks, leaves);
    DmcContour result;
    result.mesh.vertices.resize(offsets.back());
    place_vertices(grid, octrees, marks, offsets, result.mesh);
    if (progress) progress(0.75);

    std::vector<std::size_t>& first_triangle = result.first_triangle;
    first_triangle.assign(leaves + 1, 0);
    for (std::size_t leaf = 0; leaf < leaves; ++leaf) {
        first_triangle[leaf + 1] = first_triangle[leaf] + per_leaf[leaf].triangles.size();
    }
    result.mesh.triangles.resize(first_triangle.back());
    if (with_sources) result.sources.resize(first_triangle.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves), [&](const auto& range) {
        for (std::size_t leaf = range.begin(); leaf != range.end(); ++leaf) {
            const LeafTriangles& in = per_leaf[leaf];
            for (std::size_t t = 0; t < in.triangles.size(); ++t) {
                auto& triangle = result.mesh.triangles[first_triangle[leaf] + t];
                for (int k = 0; k < 3; ++k) {
                    const VertexRef ref = in.triangles[t][std::size_t(k)];
                    triangle[std::size_t(k)] = vertex_index(marks, offsets, owner_leaf(grid, leaf, ref), owner_slot(ref));
                }
            }
            if (with_sources) std::copy(in.sources.begin(), in.sources.end(), result.sources.begin() + first_triangle[leaf]);
        }
    });
    if (progress) progress(1.0);
    return result;
}

}  // namespace vdbmesh::detail
