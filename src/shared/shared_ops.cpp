// Operations on the shared tree with result matching (result_cache.h), and their plain
// references on a FloatGrid.
//
// Per-node operations (active voxels, volume) read only the node: one result per distinct
// node id, bottom-up. Neighbourhood operations (Marching Cubes, its area) read a node and the 7
// nodes after it (+x, +y, +z and their combinations: a cell's samples reach one voxel past its
// block), so their results are cached under the 8 refs; a level-L neighbourhood splits into
// the neighbourhoods of its children, each found among the 8 parents' children.

#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "vdbmesh/huge_pages.h"
#include "shared/result_cache.h"
#include "shared/shared_mc.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mc_case.h"
#include "vdbmesh/shared_tree.h"

namespace vdbmesh {

namespace detail {

namespace {

double inside_fraction(float value, double voxel) { return std::clamp(0.5 - double(value) / voxel, 0.0, 1.0); }

const std::vector<SharedRef>& children_of(const SharedTree& tree, int level, SharedRef ref) {
    return level == 2 ? tree.nodes2[ref].children : tree.nodes1[ref].children;
}

}  // namespace

ChildGrid::ChildGrid(const SharedTree& tree, int level, const Key8& parent) : m_(kSharedChildren[level] + 1) {
    const int n = m_ - 1;
    refs_.resize(std::size_t(m_) * m_ * m_);
    for (int x = 0; x < m_; ++x)
        for (int y = 0; y < m_; ++y)
            for (int z = 0; z < m_; ++z) {
                const SharedRef p = parent[(x == n) | ((y == n) << 1) | ((z == n) << 2)];
                refs_[(std::size_t(x) * m_ + y) * m_ + z] = is_tile(p) ? p : children_of(tree, level, p)[((x % n) * n + y % n) * n + z % n];
            }
}

bool quiet_key(const SharedTree& tree, const Key8& key) {
    if (!is_tile(key[0])) return false;
    const bool inside = tree.tiles[key[0] & ~kSharedTile].value < 0;
    for (SharedRef r : key) {
        if (!is_tile(r) || (tree.tiles[r & ~kSharedTile].value < 0) != inside) return false;
    }
    return true;
}

std::vector<std::pair<Coord3, Key8>> root_neighbourhoods(const SharedTree& tree) {
    std::set<Coord3> positions;
    for (const SharedRootEntry& e : tree.root) {
        for (int d = 0; d < 8; ++d) {
            positions.insert({e.origin[0] - 4096 * (d & 1), e.origin[1] - 4096 * ((d >> 1) & 1), e.origin[2] - 4096 * (d >> 2)});
        }
    }
    std::vector<std::pair<Coord3, Key8>> out;
    for (const Coord3& p : positions) {
        Key8 key;
        for (int d = 0; d < 8; ++d) {
            key[d] = tree.root_ref({p[0] + 4096 * (d & 1), p[1] + 4096 * ((d >> 1) & 1), p[2] + 4096 * (d >> 2)});
        }
        if (!quiet_key(tree, key)) out.push_back({p, key});
    }
    return out;
}

BlockMc block_marching_cubes(const SharedTree& tree, const Key8& key) {
    // The 9^3 samples the block's cells read.
    constexpr int S = 9;
    std::array<double, S * S * S> value;
    std::array<bool, S * S * S> inside;
    auto index = [](int x, int y, int z) { return (x * S + y) * S + z; };
    for (int x = 0; x < S; ++x)
        for (int y = 0; y < S; ++y)
            for (int z = 0; z < S; ++z) {
                const int d = (x == 8) | ((y == 8) << 1) | ((z == 8) << 2);
                const SharedRef r = key[d];
                const float v = is_tile(r) ? tree.tiles[r & ~kSharedTile].value
                                           : tree.leaves[r].values[((x & 7) * 8 + (y & 7)) * 8 + (z & 7)];
                value[index(x, y, z)] = double(v);
                inside[index(x, y, z)] = double(v) < 0.0;
            }
    BlockMc out;
    auto crossing = [&](int x, int y, int z, int axis) {
        const double f0 = value[index(x, y, z)];
        const double f1 = value[index(x + (axis == 0), y + (axis == 1), z + (axis == 2))];
        return std::clamp((0.0 - f0) / (f1 - f0), kMcCrossingMargin, 1.0 - kMcCrossingMargin);
    };
    std::array<std::uint16_t, 8 * 8 * 8 * 3> own;
    own.fill(detail::kMcNoEdge);
    for (int x = 0; x < 8; ++x)
        for (int y = 0; y < 8; ++y)
            for (int z = 0; z < 8; ++z)
                for (int axis = 0; axis < 3; ++axis) {
                    const int i0 = index(x, y, z), i1 = index(x + (axis == 0), y + (axis == 1), z + (axis == 2));
                    if (inside[i0] == inside[i1]) continue;
                    const std::uint16_t code = std::uint16_t(((x * 8 + y) * 8 + z) * 3 + axis);
                    own[code] = std::uint16_t(out.edges.size());
                    out.edges.push_back(code);
                    out.t.push_back(crossing(x, y, z, axis));
                }
    out.index_of.assign(own.begin(), own.end());
    // Local part: every edge the triangles use, own or not, in index space from the origin.
    std::vector<std::int32_t> part_index(S * S * S * 3, -1), borrowed_index(S * S * S * 3, -1);
    auto local_point = [&](int x, int y, int z, int axis) {
        std::array<double, 3> p = {double(x), double(y), double(z)};
        p[axis] += crossing(x, y, z, axis);
        return p;
    };
    for (int x = 0; x < 8; ++x)
        for (int y = 0; y < 8; ++y)
            for (int z = 0; z < 8; ++z) {
                unsigned config = 0;
                for (unsigned c = 0; c < 8; ++c) config |= unsigned(inside[index(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2))]) << c;
                const McCase& cell_case = mc_case(config);
                for (int t = 0; t < cell_case.triangle_count; ++t) {
                    std::array<std::uint32_t, 3> corner;
                    std::array<std::uint32_t, 3> local;
                    std::array<std::array<double, 3>, 3> p;
                    for (int k = 0; k < 3; ++k) {
                        const int edge = cell_case.triangles[t][k];
                        const unsigned c0 = kEdgeCorners[edge][0], c1 = kEdgeCorners[edge][1];
                        const int axis = (c0 ^ c1) == 1 ? 0 : (c0 ^ c1) == 2 ? 1 : 2;
                        int v[3] = {x + int(c0 & 1), y + int((c0 >> 1) & 1), z + int(c0 >> 2)};
                        const int slot = index(v[0], v[1], v[2]) * 3 + axis;
                        if (part_index[slot] < 0) {
                            part_index[slot] = std::int32_t(out.part_vertices.size());
                            const auto q = local_point(v[0], v[1], v[2], axis);
                            out.part_vertices.push_back({float(q[0]), float(q[1]), float(q[2])});
                        }
                        local[k] = std::uint32_t(part_index[slot]);
                        p[k] = local_point(v[0], v[1], v[2], axis);
                        unsigned block = 0;
                        for (int a = 0; a < 3; ++a) {
                            if (v[a] == 8) {
                                v[a] = 0;
                                block |= 1u << a;
                            }
                        }
                        const std::uint16_t code = std::uint16_t(((v[0] * 8 + v[1]) * 8 + v[2]) * 3 + axis);
                        corner[k] = block == 0 ? own[code] : 0;
                        if (block != 0) {
                            if (borrowed_index[slot] < 0) {
                                borrowed_index[slot] = std::int32_t(out.borrowed.size());
                                out.borrowed.push_back((block << 16) | code);
                            }
                            out.borrowed_corners.push_back({std::uint32_t(out.corners.size()), std::uint16_t(k), std::uint16_t(borrowed_index[slot])});
                        }
                    }
                    out.corners.push_back(corner);
                    out.part_triangles.push_back(local);
                    const double e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
                    const double e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
                    const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
                    out.area += 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
                }
            }
    return out;
}

}  // namespace detail

using detail::Key8;

std::uint64_t shared_active_voxels(const SharedTree& tree) { return shared_stats(tree).active_voxels; }

double shared_volume(const SharedTree& tree) {
    const double h = tree.voxel_size;
    // One result per distinct node, bottom-up (the cache is the per-level table itself).
    std::vector<double> leaf_volume(tree.leaves.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tree.leaves.size(), 64), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            double sum = 0;
            for (float v : tree.leaves[i].values) sum += detail::inside_fraction(v, h);
            leaf_volume[i] = sum;
        }
    });
    auto tile_volume = [&](SharedRef r, double voxels) { return detail::inside_fraction(tree.tiles[r & ~kSharedTile].value, h) * voxels; };
    std::vector<double> v1(tree.nodes1.size()), v2(tree.nodes2.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tree.nodes1.size()), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            double sum = 0;
            for (SharedRef r : tree.nodes1[i].children) sum += is_tile(r) ? tile_volume(r, 512.0) : leaf_volume[r];
            v1[i] = sum;
        }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tree.nodes2.size()), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            double sum = 0;
            for (SharedRef r : tree.nodes2[i].children) sum += is_tile(r) ? tile_volume(r, 128.0 * 128 * 128) : v1[r];
            v2[i] = sum;
        }
    });
    double sum = 0;
    for (const SharedRootEntry& e : tree.root) sum += is_tile(e.ref) ? tile_volume(e.ref, 4096.0 * 4096 * 4096) : v2[e.ref];
    return sum * h * h * h;
}

namespace {

/// The caches of one Marching Cubes run: leaf-level block results, and per level 1 and 2 the
/// area of a neighbourhood, and per level 1 the list of its surface blocks.
struct McCaches {
    detail::ResultCache<8, detail::BlockMc> blocks;
    detail::ResultCache<8, double> area1, area2;
    struct BlockRef {
        std::uint32_t offset;  ///< leaf position in the level-1 node: (x * 16 + y) * 16 + z
        const detail::BlockMc* mc;
    };
    detail::ResultCache<8, std::vector<BlockRef>> list1;
};

const detail::BlockMc& block_of(const SharedTree& tree, McCaches& caches, const Key8& key) {
    return caches.blocks.get(key, [&] { return detail::block_marching_cubes(tree, key); });
}

double area_of(const SharedTree& tree, McCaches& caches, int level, const Key8& key) {
    if (detail::quiet_key(tree, key)) return 0.0;
    if (level == 0) return block_of(tree, caches, key).area;
    auto& cache = level == 1 ? caches.area1 : caches.area2;
    return cache.get(key, [&] {
        const int n = kSharedChildren[level];
        const detail::ChildGrid children(tree, level, key);
        double sum = 0;
        for (int x = 0; x < n; ++x)
            for (int y = 0; y < n; ++y)
                for (int z = 0; z < n; ++z) sum += area_of(tree, caches, level - 1, children.key(x, y, z));
        return sum;
    });
}

const std::vector<McCaches::BlockRef>& blocks_of_level1(const SharedTree& tree, McCaches& caches, const Key8& key) {
    return caches.list1.get(key, [&] {
        std::vector<McCaches::BlockRef> list;
        const detail::ChildGrid children(tree, 1, key);
        for (int x = 0; x < 16; ++x)
            for (int y = 0; y < 16; ++y)
                for (int z = 0; z < 16; ++z) {
                    const Key8 k = children.key(x, y, z);
                    if (detail::quiet_key(tree, k)) continue;
                    const detail::BlockMc& mc = block_of(tree, caches, k);
                    if (!mc.edges.empty() || !mc.corners.empty()) list.push_back({std::uint32_t((x * 16 + y) * 16 + z), &mc});
                }
        return list;
    });
}

struct PlacedBlock {
    Coord3 origin;
    const detail::BlockMc* mc;
};

/// The blocks of the level-1 lists placed, sorted by origin without sorting them: level1 is
/// sorted by origin and each list by offset ((x * 16 + y) * 16 + z), so the blocks of one leaf
/// row (x, y) are a run of each list, taken node by node along z.
std::vector<PlacedBlock> placed_in_origin_order(const std::vector<std::pair<Coord3, Key8>>& level1,
                                                const std::vector<const std::vector<McCaches::BlockRef>*>& lists) {
    std::vector<PlacedBlock> blocks;
    std::vector<std::size_t> cursor(level1.size(), 0);
    for (std::size_t gx = 0; gx < level1.size();) {
        std::size_t gx_end = gx;  // the nodes at this x
        while (gx_end < level1.size() && level1[gx_end].first[0] == level1[gx].first[0]) ++gx_end;
        for (std::uint32_t lx = 0; lx < 16; ++lx) {
            for (std::size_t gy = gx; gy < gx_end;) {
                std::size_t gy_end = gy;  // the nodes at this x and y, by z
                while (gy_end < gx_end && level1[gy_end].first[1] == level1[gy].first[1]) ++gy_end;
                for (std::uint32_t ly = 0; ly < 16; ++ly) {
                    for (std::size_t i = gy; i < gy_end; ++i) {
                        const Coord3& o = level1[i].first;
                        const auto& list = *lists[i];
                        for (; cursor[i] < list.size() && list[cursor[i]].offset >> 4 == lx * 16 + ly; ++cursor[i]) {
                            const std::uint32_t z = list[cursor[i]].offset & 15;
                            blocks.push_back({{o[0] + int(lx) * 8, o[1] + int(ly) * 8, o[2] + int(z) * 8}, list[cursor[i]].mc});
                        }
                    }
                }
                gy = gy_end;
            }
        }
        gx = gx_end;
    }
    return blocks;
}

/// Every surface block of the tree with its cached result, sorted by origin.
std::vector<PlacedBlock> surface_blocks(const SharedTree& tree, McCaches& caches) {
    std::vector<std::pair<Coord3, Key8>> level1;  // neighbourhoods of level-1 positions
    for (const auto& [origin, key] : detail::root_neighbourhoods(tree)) {
        const detail::ChildGrid children(tree, 2, key);
        for (int x = 0; x < 32; ++x)
            for (int y = 0; y < 32; ++y)
                for (int z = 0; z < 32; ++z) {
                    const Key8 k = children.key(x, y, z);
                    if (!detail::quiet_key(tree, k)) level1.push_back({{origin[0] + x * 128, origin[1] + y * 128, origin[2] + z * 128}, k});
                }
    }
    // Root neighbourhoods at the same x give children at different x: sorted here.
    std::sort(level1.begin(), level1.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<const std::vector<McCaches::BlockRef>*> lists(level1.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, level1.size()), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) lists[i] = &blocks_of_level1(tree, caches, level1[i].second);
    });
    return placed_in_origin_order(level1, lists);
}

}  // namespace

double shared_area(const SharedTree& tree) {
    McCaches caches;
    const auto roots = detail::root_neighbourhoods(tree);
    std::vector<double> area(roots.size());
    for (std::size_t i = 0; i < roots.size(); ++i) {
        // Level-2 neighbourhoods are split here so that their children run in parallel.
        const detail::ChildGrid children(tree, 2, roots[i].second);
        std::vector<double> slab(32);
        tbb::parallel_for(0, 32, [&](int x) {
            double sum = 0;
            for (int y = 0; y < 32; ++y)
                for (int z = 0; z < 32; ++z) sum += area_of(tree, caches, 1, children.key(x, y, z));
            slab[x] = sum;
        });
        for (double s : slab) area[i] += s;
    }
    double sum = 0;
    for (double a : area) sum += a;
    return sum * tree.voxel_size * tree.voxel_size;
}

namespace {

constexpr std::uint32_t kNoBlock = ~0u;

/// For each block, the indices of the 7 blocks after it (d = 1..7 at d - 1, bits as in Key8),
/// kNoBlock where there is none. The origins shifted by one offset are sorted as the blocks
/// are, so each chunk of blocks finds them in one sweep from a binary search.
std::vector<std::array<std::uint32_t, 7>> following_blocks(const std::vector<PlacedBlock>& blocks) {
    std::vector<std::array<std::uint32_t, 7>> out(blocks.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 4096), [&](const auto& range) {
        for (unsigned d = 1; d < 8; ++d) {
            auto shifted = [&](std::size_t b) {
                const Coord3& o = blocks[b].origin;
                return Coord3{o[0] + 8 * int(d & 1), o[1] + 8 * int((d >> 1) & 1), o[2] + 8 * int(d >> 2)};
            };
            std::size_t j = std::size_t(std::lower_bound(blocks.begin(), blocks.end(), shifted(range.begin()),
                                                         [](const PlacedBlock& p, const Coord3& o) { return p.origin < o; }) -
                                        blocks.begin());
            for (std::size_t b = range.begin(); b != range.end(); ++b) {
                const Coord3 target = shifted(b);
                while (j < blocks.size() && blocks[j].origin < target) ++j;
                out[b][d - 1] = j < blocks.size() && blocks[j].origin == target ? std::uint32_t(j) : kNoBlock;
            }
        }
    });
    return out;
}

/// Offsets of each block's first vertex and first triangle in the flat mesh (one more entry
/// at the end: the totals).
void number_blocks(const std::vector<PlacedBlock>& blocks, std::vector<std::size_t>& first_vertex, std::vector<std::size_t>& first_triangle) {
    first_vertex.assign(blocks.size() + 1, 0);
    first_triangle.assign(blocks.size() + 1, 0);
    for (std::size_t b = 0; b < blocks.size(); ++b) {
        first_vertex[b + 1] = first_vertex[b] + blocks[b].mc->edges.size();
        first_triangle[b + 1] = first_triangle[b] + blocks[b].mc->corners.size();
    }
}

/// The vertices a placed block owns. The grid's transform is a uniform scale
/// (build_shared_tree()): index * h, as OpenVDB's UniformScaleMap computes it, so that the
/// vertices are mesh_grid's bit for bit.
void write_vertices(const PlacedBlock& block, double h, std::array<float, 3>* out) {
    const detail::BlockMc& mc = *block.mc;
    const Coord3& o = block.origin;
    for (std::size_t e = 0; e < mc.edges.size(); ++e) {
        const unsigned code = mc.edges[e];
        const unsigned axis = code % 3, cell = code / 3;
        // x + 0.0 off the axis, as edge_crossing() computes p0 + t * (p1 - p0); no array
        // indexed by the axis (its store and reload stalled this loop).
        const double t = mc.t[e];
        const double x = double(o[0] + int(cell >> 6)) + (axis == 0 ? t : 0.0);
        const double y = double(o[1] + int((cell >> 3) & 7)) + (axis == 1 ? t : 0.0);
        const double z = double(o[2] + int(cell & 7)) + (axis == 2 ? t : 0.0);
        out[e] = {float(x * h), float(y * h), float(z * h)};
    }
}

/// The mesh indices of the vertices block @a b borrows, in BlockMc::borrowed order.
void borrowed_vertices(const std::vector<PlacedBlock>& blocks, const std::vector<std::array<std::uint32_t, 7>>& following,
                       const std::vector<std::size_t>& first_vertex, std::size_t b, std::vector<std::uint32_t>& out) {
    const detail::BlockMc& mc = *blocks[b].mc;
    out.resize(mc.borrowed.size());
    for (std::size_t j = 0; j < mc.borrowed.size(); ++j) {
        const unsigned d = mc.borrowed[j] >> 16, code = mc.borrowed[j] & 0xffffu;
        const std::uint32_t n = following[b][d - 1];
        if (n == kNoBlock) throw Error("shared marching cubes: a triangle refers to a missing block");
        const std::uint16_t index = blocks[n].mc->index_of[code];
        if (index == detail::kMcNoEdge) throw Error("shared marching cubes: a triangle refers to a missing vertex");
        out[j] = std::uint32_t(first_vertex[n] + index);
    }
}

/// A placed block's triangles: the cached corners plus the block's first vertex (a copy the
/// compiler vectorises), then the borrowed corners overwritten.
void write_triangles(const detail::BlockMc& mc, std::uint32_t first_vertex, const std::vector<std::uint32_t>& borrowed,
                     std::array<std::uint32_t, 3>* out) {
    for (std::size_t t = 0; t < mc.corners.size(); ++t) {
        out[t] = {mc.corners[t][0] + first_vertex, mc.corners[t][1] + first_vertex, mc.corners[t][2] + first_vertex};
    }
    for (const auto& c : mc.borrowed_corners) out[c.triangle][c.corner] = borrowed[c.borrowed];
}

}  // namespace

// The flat mesh: every placed block numbers the vertices it owns from its offset (prefix sums
// over the blocks in origin order) and finds the ones it borrows in the neighbours' cached
// index_of; vertices and triangles are written per block in parallel at their offsets. No
// table of global edges, no welding afterwards: the same welded mesh for any thread count.
Mesh shared_marching_cubes(const SharedTree& tree) {
    McCaches caches;
    const std::vector<PlacedBlock> blocks = surface_blocks(tree, caches);
    std::vector<std::size_t> first_vertex, first_triangle;
    number_blocks(blocks, first_vertex, first_triangle);
    if (first_vertex.back() > std::numeric_limits<std::uint32_t>::max()) throw Error("shared marching cubes: more than 2^32 vertices");
    std::vector<std::array<std::uint32_t, 7>> following;
    Mesh mesh;
    // Some hundred MB written once: huge pages save most of the page faults (vdbmesh/huge_pages.h);
    // the two arrays are allocated (and zeroed, serially each) side by side.
    tbb::parallel_invoke([&] { following = following_blocks(blocks); },
                         [&] {
                             detail::reserve_on_huge_pages(mesh.vertices, first_vertex.back());
                             mesh.vertices.resize(first_vertex.back());
                         },
                         [&] {
                             detail::reserve_on_huge_pages(mesh.triangles, first_triangle.back());
                             mesh.triangles.resize(first_triangle.back());
                         });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 64), [&](const auto& range) {
        std::vector<std::uint32_t> borrowed;
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            write_vertices(blocks[b], tree.voxel_size, mesh.vertices.data() + first_vertex[b]);
            borrowed_vertices(blocks, following, first_vertex, b, borrowed);
            write_triangles(*blocks[b].mc, std::uint32_t(first_vertex[b]), borrowed, mesh.triangles.data() + first_triangle[b]);
        }
    });
    return mesh;
}

InstancedMesh shared_marching_cubes_instanced(const SharedTree& tree) {
    McCaches caches;
    const std::vector<PlacedBlock> blocks = surface_blocks(tree, caches);
    InstancedMesh out;
    std::unordered_map<const detail::BlockMc*, std::uint32_t> part_of;
    const double h = tree.voxel_size;
    for (const PlacedBlock& b : blocks) {
        if (b.mc->corners.empty()) continue;
        const auto [it, inserted] = part_of.emplace(b.mc, std::uint32_t(out.parts.size()));
        if (inserted) {
            Mesh part;
            part.vertices.reserve(b.mc->part_vertices.size());
            for (const auto& v : b.mc->part_vertices) part.vertices.push_back({float(v[0] * h), float(v[1] * h), float(v[2] * h)});
            part.triangles = b.mc->part_triangles;
            out.parts.push_back(std::move(part));
        }
        out.instances.push_back({it->second, {b.origin[0] * h, b.origin[1] * h, b.origin[2] * h}});
    }
    return out;
}

// ---- Plain references --------------------------------------------------------------------------

std::uint64_t plain_active_voxels(const openvdb::FloatGrid& grid) { return grid.tree().activeVoxelCount(); }

double plain_volume(const openvdb::FloatGrid& grid) {
    const double h = grid.voxelSize()[0];
    double sum = 0;
    for (auto it = grid.tree().cbeginValueAll(); it; ++it) {
        sum += detail::inside_fraction(*it, h) * double(it.getVoxelCount());
    }
    const double bg = detail::inside_fraction(grid.background(), h);
    if (bg != 0.0) throw UsageError("plain volume: the background is inside (infinite volume)");
    return sum * h * h * h;
}

}  // namespace vdbmesh
