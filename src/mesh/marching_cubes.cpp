// Marching Cubes (Lorensen and Cline, SIGGRAPH 1987) on the samples of a sparse grid, with the
// crack-free table of mc_table.cpp. Vertices are keyed by their grid edge (the edge's minimum
// voxel and its axis), as in the topology-recovery note 003_*.txt, so they are welded exactly
// with no coordinate hashing. The work is split in 8^3 blocks of cells (surface_blocks()),
// taken in the bricks' order (node by node in z-major order, a node's blocks by origin), so
// that the mesh made brick by brick (marching_cubes_nodes(), through DC's spill) has the
// same bytes:
//  1. per block, in parallel: the crossing edges it owns (those whose minimum voxel lies in it)
//     with their positions, and its triangles as references to edges of this block or of the
//     7 blocks a step further along x, y or z;
//  2. serial prefix sums over the blocks' vertex and triangle counts;
//  3. per block, in parallel: vertices and triangles written at their offsets.
// The output therefore depends on the grid and options only, not on the thread count.
//
// Inside/outside, the scan box and the crossing points follow edge_crossing.h, so that DC at
// error 0 gives the same vertices. Every triangle has three distinct vertices (on three distinct
// edges) and, the crossings being kept off the samples, non-zero area: three interior points
// of three distinct edges of a cube are never collinear.

#include "mesh/marching_cubes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "mesh/dual_contouring.h"
#include "mesh/edge_crossing.h"
#include "mesh/mc_table.h"
#include "mesh/sample_classifier.h"
#include "mesh/surface_blocks.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

constexpr int kCacheDim = kBlockDim + 1;  // a block's cells use samples 0..kBlockDim on each axis

/// The values (edge_crossing.h: outside_scan_value() beyond the box) of the samples a block's
/// cells read, with their classification.
struct BlockSamples {
    openvdb::Coord origin;
    std::array<double, kCacheDim * kCacheDim * kCacheDim> value;
    std::array<bool, kCacheDim * kCacheDim * kCacheDim> inside;

    static int index(int x, int y, int z) { return (x * kCacheDim + y) * kCacheDim + z; }
};

void load_samples(openvdb::FloatGrid::ConstAccessor& accessor, const SampleClassifier& classifier,
                  BlockSamples& samples) {
    for (int x = 0; x < kCacheDim; ++x) {
        for (int y = 0; y < kCacheDim; ++y) {
            for (int z = 0; z < kCacheDim; ++z) {
                const openvdb::Coord ijk = samples.origin.offsetBy(x, y, z);
                const int i = BlockSamples::index(x, y, z);
                samples.value[i] = classifier.sample_value(ijk, accessor.getValue(ijk));
                samples.inside[i] = classifier.inside(samples.value[i]);
            }
        }
    }
}

/// An edge owned by a block: ((x * 8 + y) * 8 + z) * 3 + axis for its minimum voxel (x, y, z)
/// relative to the block's origin.
std::uint16_t edge_code(int x, int y, int z, int axis) {
    return std::uint16_t(((x * kBlockDim + y) * kBlockDim + z) * 3 + axis);
}

/// A triangle corner. An edge of the triangle's own block: kOwnVertex | the vertex's index in
/// that block. Otherwise: the owning block as an offset d (bit a set: next block along axis a)
/// in bits 16-18, the edge_code() in the low 16.
using EdgeRef = std::uint32_t;
constexpr EdgeRef kOwnVertex = 1u << 31;

constexpr int kBlockEdges = kBlockDim * kBlockDim * kBlockDim * 3;
/// Per task: the index in its block of each owned crossing edge, by edge_code() (only the
/// entries of the current block's crossing edges are meaningful).
using OwnVertexIndex = std::array<std::uint16_t, kBlockEdges>;

struct BlockOutput {
    std::vector<std::uint16_t> edges;  ///< owned crossing edges, sorted
    std::vector<std::array<float, 3>> positions;
    std::vector<std::array<EdgeRef, 3>> triangles;
};

/// The blocks' output order: node by node in z-major order (the bricks' order), then by
/// origin within a node.
bool block_before(const openvdb::Coord& a, const openvdb::Coord& b) {
    const openvdb::Coord node_a = ifc_node_of(a), node_b = ifc_node_of(b);
    return node_a != node_b ? ifc_node_before(node_a, node_b) : a < b;
}

/// Marching Cubes on the blocks of a grid, each block's output apart.
class MarchingCubes {
public:
    MarchingCubes(const openvdb::FloatGrid& grid, const SampleClassifier& classifier, const MeshOptions& options,
                  const std::optional<openvdb::CoordBBox>& within = std::nullopt)
        : grid_(grid), options_(options), classifier_(classifier), blocks_(surface_blocks(grid, classifier, within)) {
        std::sort(blocks_.begin(), blocks_.end(), block_before);
    }

    /// Each block's crossing edges, their positions and its triangles.
    std::vector<BlockOutput> march() const {
        std::vector<BlockOutput> outputs(blocks_.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size()), [&](const auto& range) {
            auto accessor = grid_.getConstAccessor();
            BlockSamples samples;
            OwnVertexIndex own_vertex;
            for (std::size_t b = range.begin(); b != range.end(); ++b) {
                if (!block_may_hold_surface(accessor, classifier_, blocks_[b])) continue;  // most blocks next to a leaf
                samples.origin = blocks_[b];
                load_samples(accessor, classifier_, samples);
                collect_vertices(samples, own_vertex, outputs[b]);
                collect_triangles(samples, own_vertex, outputs[b]);
            }
        });
        return outputs;
    }

    /// The mesh of every block: vertices and triangles in the blocks' order.
    Mesh assemble(const std::vector<BlockOutput>& outputs) const;

    /// The blocks' outputs keyed as DC's nodes are (ifc_edge_key()), grouped by node.
    std::vector<IfcNodeOutput> keyed_nodes(std::vector<BlockOutput>&& outputs) const;

private:
    /// Whether the crossing edge at @a v along @a axis carries a vertex: with open_boundary,
    /// only when a cell lying in the box uses it.
    bool edge_has_vertex(const openvdb::Coord& v, int axis) const {
        if (!options_.open_boundary) return true;
        const int u = (axis + 1) % 3, w = (axis + 2) % 3;
        for (int d = 0; d < 4; ++d) {
            openvdb::Coord cell = v;
            cell[u] -= d & 1;
            cell[w] -= d >> 1;
            if (classifier_.cell_in_box(cell)) return true;
        }
        return false;
    }

    void collect_vertices(const BlockSamples& samples, OwnVertexIndex& own_vertex, BlockOutput& out) const {
        const openvdb::math::Transform& transform = grid_.transform();
        for (int x = 0; x < kBlockDim; ++x) {
            for (int y = 0; y < kBlockDim; ++y) {
                for (int z = 0; z < kBlockDim; ++z) {
                    const int i0 = BlockSamples::index(x, y, z);
                    for (int axis = 0; axis < 3; ++axis) {
                        const int i1 = BlockSamples::index(x + (axis == 0), y + (axis == 1), z + (axis == 2));
                        if (samples.inside[i0] == samples.inside[i1]) continue;
                        const openvdb::Coord v = samples.origin.offsetBy(x, y, z);
                        if (!edge_has_vertex(v, axis)) continue;
                        const Point3d p0 = {double(v.x()), double(v.y()), double(v.z())};
                        Point3d p1 = p0;
                        p1[axis] += 1.0;
                        const Point3d p = edge_crossing(p0, samples.value[i0], p1, samples.value[i1], classifier_.iso());
                        const openvdb::Vec3d world = transform.indexToWorld(openvdb::Vec3d(p[0], p[1], p[2]));
                        own_vertex[edge_code(x, y, z, axis)] = std::uint16_t(out.edges.size());
                        out.edges.push_back(edge_code(x, y, z, axis));
                        out.positions.push_back({float(world[0]), float(world[1]), float(world[2])});
                    }
                }
            }
        }
    }

    void collect_triangles(const BlockSamples& samples, const OwnVertexIndex& own_vertex, BlockOutput& out) const {
        for (int x = 0; x < kBlockDim; ++x) {
            for (int y = 0; y < kBlockDim; ++y) {
                for (int z = 0; z < kBlockDim; ++z) {
                    unsigned config = 0;
                    for (unsigned c = 0; c < 8; ++c) {
                        config |= unsigned(samples.inside[BlockSamples::index(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2))]) << c;
                    }
                    const McCase& cell_case = mc_case(config);
                    if (cell_case.triangle_count == 0) continue;
                    if (options_.open_boundary && !classifier_.cell_in_box(samples.origin.offsetBy(x, y, z))) continue;
                    for (int t = 0; t < cell_case.triangle_count; ++t) {
                        std::array<EdgeRef, 3> refs;
                        for (int k = 0; k < 3; ++k) refs[k] = edge_ref(x, y, z, cell_case.triangles[t][k], own_vertex);
                        out.triangles.push_back(refs);
                    }
                }
            }
        }
    }

    /// The reference to cell edge @a edge of the cell at (x, y, z) in its block.
    static EdgeRef edge_ref(int x, int y, int z, int edge, const OwnVertexIndex& own_vertex) {
        const unsigned c0 = kEdgeCorners[edge][0], c1 = kEdgeCorners[edge][1];
        const int axis = (c0 ^ c1) == 1 ? 0 : (c0 ^ c1) == 2 ? 1 : 2;
        std::array<int, 3> v = {x + int(c0 & 1), y + int((c0 >> 1) & 1), z + int(c0 >> 2)};
        unsigned block = 0;
        for (int a = 0; a < 3; ++a) {
            if (v[a] == kBlockDim) {
                v[a] = 0;
                block |= 1u << a;
            }
        }
        const std::uint16_t code = edge_code(v[0], v[1], v[2], axis);
        return block == 0 ? kOwnVertex | own_vertex[code] : (block << 16) | code;
    }

    /// The index in blocks_ of the block at @a origin.
    std::size_t block_index(const openvdb::Coord& origin) const {
        const auto it = std::lower_bound(blocks_.begin(), blocks_.end(), origin, block_before);
        if (it == blocks_.end() || *it != origin) throw Error("marching cubes: a triangle refers to an unvisited block");
        return std::size_t(it - blocks_.begin());
    }

    const openvdb::FloatGrid& grid_;
    const MeshOptions& options_;
    const SampleClassifier& classifier_;
    std::vector<openvdb::Coord> blocks_;
};

Mesh MarchingCubes::assemble(const std::vector<BlockOutput>& outputs) const {
    std::vector<std::size_t> first_vertex(outputs.size() + 1, 0), first_triangle(outputs.size() + 1, 0);
    for (std::size_t b = 0; b < outputs.size(); ++b) {
        first_vertex[b + 1] = first_vertex[b] + outputs[b].positions.size();
        first_triangle[b + 1] = first_triangle[b] + outputs[b].triangles.size();
    }
    if (first_vertex.back() > std::numeric_limits<std::uint32_t>::max()) {
        throw Error("marching cubes: more than 2^32 vertices");
    }
    Mesh mesh;
    mesh.vertices.resize(first_vertex.back());
    mesh.triangles.resize(first_triangle.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, outputs.size()), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            const BlockOutput& out = outputs[b];
            std::copy(out.positions.begin(), out.positions.end(), mesh.vertices.begin() + first_vertex[b]);
            // The blocks a triangle of block b can refer to: b itself and the 7 after it.
            // Edges of b are resolved already; the others are found by binary search.
            std::array<std::size_t, 8> neighbour{};
            std::array<bool, 8> resolved{};
            auto vertex_index = [&](EdgeRef ref) {
                if (ref & kOwnVertex) return std::uint32_t(first_vertex[b] + (ref & 0xffffu));
                const unsigned d = ref >> 16;
                if (!resolved[d]) {
                    neighbour[d] = block_index(blocks_[b].offsetBy(kBlockDim * (d & 1), kBlockDim * ((d >> 1) & 1), kBlockDim * (d >> 2)));
                    resolved[d] = true;
                }
                const std::vector<std::uint16_t>& edges = outputs[neighbour[d]].edges;
                const auto it = std::lower_bound(edges.begin(), edges.end(), std::uint16_t(ref & 0xffffu));
                if (it == edges.end() || *it != (ref & 0xffffu)) throw Error("marching cubes: a triangle refers to a missing vertex");
                return std::uint32_t(first_vertex[neighbour[d]] + std::size_t(it - edges.begin()));
            };
            for (std::size_t t = 0; t < out.triangles.size(); ++t) {
                auto& tri = mesh.triangles[first_triangle[b] + t];
                for (int k = 0; k < 3; ++k) tri[k] = vertex_index(out.triangles[t][k]);
            }
        }
    });
    return mesh;
}

std::vector<IfcNodeOutput> MarchingCubes::keyed_nodes(std::vector<BlockOutput>&& outputs) const {
    // The grid edge of an edge_code() in the block at @a block: its minimum voxel and axis.
    auto edge_of = [](const openvdb::Coord& block, std::uint32_t code) {
        const int axis = int(code % 3), cell = int(code / 3);
        return std::pair{block.offsetBy(cell / (kBlockDim * kBlockDim), (cell / kBlockDim) % kBlockDim, cell % kBlockDim), axis};
    };
    std::vector<IfcNodeOutput> nodes;
    for (std::size_t b = 0; b < blocks_.size(); ++b) {
        BlockOutput& out = outputs[b];
        if (out.edges.empty() && out.triangles.empty()) continue;
        const openvdb::Coord& origin = blocks_[b];
        const openvdb::Coord node = ifc_node_of(origin);
        if (nodes.empty() || nodes.back().origin != node) nodes.push_back({node, {}, {}});
        IfcBlockOutput keyed;
        keyed.vertices.reserve(out.edges.size());
        for (std::size_t v = 0; v < out.edges.size(); ++v) {
            const auto [voxel, axis] = edge_of(origin, out.edges[v]);
            keyed.vertices.push_back({ifc_edge_key(voxel, axis), out.positions[v]});
        }
        keyed.triangles.reserve(out.triangles.size());
        for (const std::array<EdgeRef, 3>& refs : out.triangles) {
            std::array<std::uint64_t, 3> keys;
            for (int k = 0; k < 3; ++k) {
                if (refs[k] & kOwnVertex) {
                    keys[k] = keyed.vertices[refs[k] & 0xffffu].key;
                    continue;
                }
                const unsigned d = refs[k] >> 16;
                const openvdb::Coord neighbour = origin.offsetBy(kBlockDim * int(d & 1), kBlockDim * int((d >> 1) & 1), kBlockDim * int(d >> 2));
                const auto [voxel, axis] = edge_of(neighbour, refs[k] & 0xffffu);
                keys[k] = ifc_edge_key(voxel, axis);
            }
            keyed.triangles.push_back(keys);
        }
        out = BlockOutput();
        nodes.back().blocks.push_back(std::move(keyed));
    }
    return nodes;
}

}  // namespace

Mesh marching_cubes(const openvdb::FloatGrid& grid, const MeshOptions& options) {
    const SampleClassifier classifier(grid, options);
    const MarchingCubes marcher(grid, classifier, options);
    const std::vector<BlockOutput> outputs = marcher.march();
    if (options.progress) options.progress(0.7);
    Mesh mesh = marcher.assemble(outputs);
    if (options.progress) options.progress(1.0);
    return mesh;
}

std::vector<IfcNodeOutput> marching_cubes_nodes(const openvdb::FloatGrid& grid, const SampleClassifier& classifier, const MeshOptions& options,
                                                const openvdb::CoordBBox& blocks_within) {
    const MarchingCubes marcher(grid, classifier, options, blocks_within);
    return marcher.keyed_nodes(marcher.march());
}

}  // namespace vdbmesh::detail
