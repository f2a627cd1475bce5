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
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
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

ChildGrid::ChildGrid(const SharedTree& tree, int level, const Key8& parent)
    : m_(kSharedChildren[level] + 1), tile_(is_tile(parent[0])) {
    const int n = m_ - 1;
    // The parents' children (null for a tile) looked up once; coordinate n is a next parent's 0.
    std::array<const SharedRef*, 8> children;
    for (int d = 0; d < 8; ++d) children[d] = is_tile(parent[d]) ? nullptr : children_of(tree, level, parent[d]).data();
    refs_.resize(std::size_t(m_) * m_ * m_);
    for (int x = 0; x < m_; ++x)
        for (int y = 0; y < m_; ++y)
            for (int z = 0; z < m_; ++z) {
                const int d = (x == n) | ((y == n) << 1) | ((z == n) << 2);
                const int i = ((x == n ? 0 : x) * n + (y == n ? 0 : y)) * n + (z == n ? 0 : z);
                refs_[(std::size_t(x) * m_ + y) * m_ + z] = children[d] ? children[d][i] : parent[d];
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

BlockMc block_marching_cubes(const SharedTree& tree, const Key8& key, bool with_part) {
    // The 9^3 samples the block's cells read.
    constexpr int S = 9;
    std::array<double, S * S * S> value;
    // Inside (value < 0) as bits: bit z of rows[x * S + y]. Most rows of a block see no sign
    // change, and the edge and cell scans below skip them whole.
    std::array<std::uint16_t, S * S> rows{};
    auto index = [](int x, int y, int z) { return (x * S + y) * S + z; };
    for (int x = 0; x < S; ++x)
        for (int y = 0; y < S; ++y)
            for (int z = 0; z < S; ++z) {
                const int d = (x == 8) | ((y == 8) << 1) | ((z == 8) << 2);
                const SharedRef r = key[d];
                const float v = is_tile(r) ? tree.tiles[r & ~kSharedTile].value
                                           : tree.leaves[r].values[((x & 7) * 8 + (y & 7)) * 8 + (z & 7)];
                value[index(x, y, z)] = double(v);
                if (double(v) < 0.0) rows[x * S + y] |= std::uint16_t(1u << z);
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
        for (int y = 0; y < 8; ++y) {
            // Bit z of crosses[axis]: the edge from (x, y, z) along axis crosses.
            const unsigned r = rows[x * S + y];
            const unsigned crosses[3] = {(r ^ rows[(x + 1) * S + y]) & 0xffu, (r ^ rows[x * S + y + 1]) & 0xffu, (r ^ (r >> 1)) & 0xffu};
            for (unsigned any = crosses[0] | crosses[1] | crosses[2]; any != 0; any &= any - 1) {
                const int z = __builtin_ctz(any);
                for (int axis = 0; axis < 3; ++axis) {
                    if (!((crosses[axis] >> z) & 1u)) continue;
                    own[((x * 8 + y) * 8 + z) * 3 + axis] = std::uint16_t(out.owned.size());
                    detail::BlockMc::OwnedVertex v = {{x, y, z}, {0.0, 0.0, 0.0}};
                    v.along[axis] = crossing(x, y, z, axis);
                    out.owned.push_back(v);
                }
            }
        }
    for (int face = 0; face < 3; ++face)
        for (int u = 0; u < 8; ++u)
            for (int v = 0; v < 8; ++v) {
                int c[3];
                c[face] = 0;
                c[face == 0 ? 1 : 0] = u;
                c[face == 2 ? 1 : 2] = v;
                for (int axis = 0; axis < 3; ++axis) out.face_index[face_slot(face, c, axis)] = own[((c[0] * 8 + c[1]) * 8 + c[2]) * 3 + axis];
            }
    // Local part: every edge the triangles use, own or not, in index space from the origin.
    std::vector<std::int32_t> part_index(with_part ? S * S * S * 3 : 0, -1), borrowed_index(S * S * S * 3, -1);
    std::vector<std::array<double, 3>> part_points;  // part_vertices in double, for the area
    auto local_point = [&](int x, int y, int z, int axis) {
        std::array<double, 3> p = {double(x), double(y), double(z)};
        p[axis] += crossing(x, y, z, axis);
        return p;
    };
    // The cells with corners on both sides, in (x, y, z) order, with their cases (cells with all
    // corners on one side have none); the triangle count sizes the outputs once.
    struct Cell {
        std::uint16_t position;  // (x * 8 + y) * 8 + z
        const McCase* cell_case;
    };
    std::array<Cell, 8 * 8 * 8> cells;
    std::size_t cell_count = 0, triangle_count = 0;
    for (int x = 0; x < 8; ++x)
        for (int y = 0; y < 8; ++y) {
            // The cell's corner c = dx + 2 dy + 4 dz is bit z + dz of corner_rows[dx + 2 dy].
            const unsigned corner_rows[4] = {rows[x * S + y], rows[(x + 1) * S + y], rows[x * S + y + 1], rows[(x + 1) * S + y + 1]};
            const unsigned across = (corner_rows[0] ^ corner_rows[1]) | (corner_rows[0] ^ corner_rows[2]) | (corner_rows[0] ^ corner_rows[3]);
            for (unsigned mixed = (across | (across >> 1) | (corner_rows[0] ^ (corner_rows[0] >> 1))) & 0xffu; mixed != 0; mixed &= mixed - 1) {
                const int z = __builtin_ctz(mixed);
                unsigned config = 0;
                for (unsigned c = 0; c < 8; ++c) config |= ((corner_rows[c & 3] >> (z + int(c >> 2))) & 1u) << c;
                cells[cell_count] = {std::uint16_t((x * 8 + y) * 8 + z), &mc_case(config)};
                triangle_count += cells[cell_count++].cell_case->triangle_count;
            }
        }
    out.corners.reserve(triangle_count);
    if (with_part) out.part_triangles.reserve(triangle_count);
    for (std::size_t i = 0; i < cell_count; ++i) {
        const int x = cells[i].position >> 6, y = (cells[i].position >> 3) & 7, z = cells[i].position & 7;
        const McCase& cell_case = *cells[i].cell_case;
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
                if (with_part) {
                    if (part_index[slot] < 0) {
                        part_index[slot] = std::int32_t(out.part_vertices.size());
                        const auto q = local_point(v[0], v[1], v[2], axis);
                        out.part_vertices.push_back({float(q[0]), float(q[1]), float(q[2])});
                        part_points.push_back(q);
                    }
                    local[k] = std::uint32_t(part_index[slot]);
                    p[k] = part_points[local[k]];
                }
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
                        const int face = block & 1 ? 0 : block & 2 ? 1 : 2;  // v[face] is 0
                        out.borrowed.push_back((block << 16) | unsigned(face_slot(face, v, axis)));
                    }
                    out.borrowed_corners.push_back({std::uint32_t(out.corners.size()), std::uint16_t(k), std::uint16_t(borrowed_index[slot])});
                }
            }
            out.corners.push_back(corner);
            if (!with_part) continue;
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
    /// Whether the blocks get their part (BlockMc::part_vertices, part_triangles) and area:
    /// the instanced mesh and the area read them, the flat mesh does not.
    bool parts = true;
    detail::ResultCache<8, detail::BlockMc> blocks;
    detail::ResultCache<8, double> area1, area2;
    struct BlockRef {
        std::uint32_t offset;  ///< leaf position in the level-1 node: (x * 16 + y) * 16 + z
        const detail::BlockMc* mc;
    };
    detail::ResultCache<8, std::vector<BlockRef>> list1;
};

const detail::BlockMc& block_of(const SharedTree& tree, McCaches& caches, const Key8& key) {
    return caches.blocks.get(key, [&] { return detail::block_marching_cubes(tree, key, caches.parts); });
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
                    if (children.inside_tile(x, y, z)) continue;
                    const Key8 k = children.key(x, y, z);
                    if (detail::quiet_key(tree, k)) continue;
                    const detail::BlockMc& mc = block_of(tree, caches, k);
                    if (!mc.owned.empty() || !mc.corners.empty()) list.push_back({std::uint32_t((x * 16 + y) * 16 + z), &mc});
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
    std::size_t count = 0;
    for (const auto* list : lists) count += list->size();
    std::vector<PlacedBlock> blocks;
    blocks.reserve(count);
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
    // The neighbourhoods of level-1 positions, gathered in parallel per slab of a root
    // neighbourhood's children (fixed x) and joined in slab order.
    const auto roots = detail::root_neighbourhoods(tree);
    std::vector<std::unique_ptr<const detail::ChildGrid>> children(roots.size());
    tbb::parallel_for(std::size_t(0), roots.size(), [&](std::size_t r) { children[r] = std::make_unique<const detail::ChildGrid>(tree, 2, roots[r].second); });
    std::vector<std::vector<std::pair<Coord3, Key8>>> slabs(roots.size() * 32);
    tbb::parallel_for(std::size_t(0), slabs.size(), [&](std::size_t i) {
        const Coord3& origin = roots[i / 32].first;
        const int x = int(i % 32);
        for (int y = 0; y < 32; ++y)
            for (int z = 0; z < 32; ++z) {
                if (children[i / 32]->inside_tile(x, y, z)) continue;
                const Key8 k = children[i / 32]->key(x, y, z);
                if (!detail::quiet_key(tree, k)) slabs[i].push_back({{origin[0] + x * 128, origin[1] + y * 128, origin[2] + z * 128}, k});
            }
    });
    std::vector<std::pair<Coord3, Key8>> level1;
    for (const auto& slab : slabs) level1.insert(level1.end(), slab.begin(), slab.end());
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
/// A block's most owned vertices (every edge) and triangles (every cell the most of a case).
constexpr std::size_t kMaxBlockVertices = 8 * 8 * 8 * 3,
                      kMaxBlockTriangles = 8 * 8 * 8 * std::tuple_size<decltype(detail::McCase::triangles)>::value;

/// The pages of an array that one thread appends to, faulted in a little ahead of it by
/// another thread with time to spare: the kernel's zeroing of fresh pages (about half the cost
/// of a first write) moves to that thread, while the pages are still in cache when the writer
/// reaches them (faulted far ahead, they are not, and the writer saved little: measured).
/// Only page faults move: what is written, and by which thread, stays the same. Nobody waits.
class PagesAhead {
public:
    PagesAhead(const void* data, std::size_t bytes)
        : base_(reinterpret_cast<std::uintptr_t>(data)), end_(base_ + bytes), written_(base_) {
        next_ = (base_ + kHugePage - 1) & ~(kHugePage - 1);  // whole huge pages; the writer faults the first one
    }
    /// By the writer: its bytes written so far.
    void written(std::size_t bytes) { written_.store(base_ + bytes, std::memory_order_relaxed); }
    /// Whether the writer has written less than @a fraction of the array.
    bool behind(double fraction) const {
        return double(written_.load(std::memory_order_relaxed) - base_) < fraction * double(end_ - base_);
    }
    /// By the helper: faults the pages up to kAhead past the writer.
    void keep_ahead() {
        const std::uintptr_t w = written_.load(std::memory_order_relaxed);
        if (next_ < w) next_ = (w + kHugePage - 1) & ~(kHugePage - 1);  // the writer went past
        for (const std::uintptr_t limit = std::min(end_, w + kAhead); next_ < limit; next_ += kHugePage) {
            detail::populate_pages(reinterpret_cast<void*>(next_), std::min(kHugePage, end_ - next_));
        }
    }

private:
    static constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20, kAhead = 4 * kHugePage;
    std::uintptr_t base_, end_, next_;
    std::atomic<std::uintptr_t> written_;  // base_ + bytes written
};

/// The 7 blocks after each block in turn (d = 1..7 at d - 1, bits as in Key8; kNoBlock where
/// there is none), found by one sweep along the blocks: the origins shifted by one offset are
/// sorted as the blocks are, so each direction's cursor only moves forward.
class FollowingSweep {
public:
    explicit FollowingSweep(const std::vector<PlacedBlock>& blocks) : blocks_(blocks) { cursor_.fill(0); }
    /// The blocks after block @a b; @a b must not decrease from one call to the next.
    std::array<std::uint32_t, 7> after(std::size_t b) {
        std::array<std::uint32_t, 7> out;
        const Coord3& o = blocks_[b].origin;
        for (unsigned d = 1; d < 8; ++d) {
            const Coord3 target = {o[0] + 8 * int(d & 1), o[1] + 8 * int((d >> 1) & 1), o[2] + 8 * int(d >> 2)};
            std::size_t& j = cursor_[d - 1];
            while (j < blocks_.size() && before(blocks_[j].origin, target)) ++j;
            out[d - 1] = j < blocks_.size() && same(blocks_[j].origin, target) ? std::uint32_t(j) : kNoBlock;
        }
        return out;
    }

private:
    // Written out: std::array's == is a memcmp call, which dominated the sweep.
    static bool before(const Coord3& a, const Coord3& b) {
        return a[0] != b[0] ? a[0] < b[0] : a[1] != b[1] ? a[1] < b[1] : a[2] < b[2];
    }
    static bool same(const Coord3& a, const Coord3& b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }
    const std::vector<PlacedBlock>& blocks_;
    std::array<std::size_t, 7> cursor_;
};

/// Offsets of each block's first vertex and first triangle in the flat mesh (one more entry
/// at the end: the totals).
void number_blocks(const std::vector<PlacedBlock>& blocks, std::vector<std::size_t>& first_vertex, std::vector<std::size_t>& first_triangle) {
    first_vertex.assign(blocks.size() + 1, 0);
    first_triangle.assign(blocks.size() + 1, 0);
    for (std::size_t b = 0; b < blocks.size(); ++b) {
        first_vertex[b + 1] = first_vertex[b] + blocks[b].mc->owned.size();
        first_triangle[b + 1] = first_triangle[b] + blocks[b].mc->corners.size();
    }
}

/// The vertices a placed block owns. The grid's transform is a uniform scale
/// (build_shared_tree()): index * h, as OpenVDB's UniformScaleMap computes it, so that the
/// vertices are mesh_grid's bit for bit.
void write_vertices(const PlacedBlock& block, double h, std::array<float, 3>* out) {
    const Coord3& o = block.origin;
    const auto& owned = block.mc->owned;
    for (std::size_t e = 0; e < owned.size(); ++e) {
        const auto& v = owned[e];
        out[e] = {float((double(o[0] + v.corner[0]) + v.along[0]) * h), float((double(o[1] + v.corner[1]) + v.along[1]) * h),
                  float((double(o[2] + v.corner[2]) + v.along[2]) * h)};
    }
}

/// The mesh indices of the vertices block @a b borrows, in BlockMc::borrowed order. The
/// neighbours' first vertices and face tables are looked up once per direction (per borrowed
/// vertex, the chain of loads stood out in profiles).
void borrowed_vertices(const std::vector<PlacedBlock>& blocks, const std::array<std::uint32_t, 7>& following,
                       const std::vector<std::size_t>& first_vertex, std::size_t b, std::vector<std::uint32_t>& out) {
    std::array<const std::uint16_t*, 7> face_index{};
    std::array<std::uint32_t, 7> first{};
    for (std::size_t d = 0; d < 7; ++d) {
        if (following[d] == kNoBlock) continue;
        face_index[d] = blocks[following[d]].mc->face_index.data();
        first[d] = std::uint32_t(first_vertex[following[d]]);
    }
    const detail::BlockMc& mc = *blocks[b].mc;
    out.resize(mc.borrowed.size());
    for (std::size_t j = 0; j < mc.borrowed.size(); ++j) {
        const unsigned d = (mc.borrowed[j] >> 16) - 1, slot = mc.borrowed[j] & 0xffffu;
        if (face_index[d] == nullptr) throw Error("shared marching cubes: a triangle refers to a missing block");
        const std::uint16_t index = face_index[d][slot];
        if (index == detail::kMcNoEdge) throw Error("shared marching cubes: a triangle refers to a missing vertex");
        out[j] = first[d] + index;
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

/// The @a count vertices of the placed blocks in order, appended to @a out (reserved). While it is
/// ahead of the triangles (in the fraction of its output written), it faults their pages ahead
/// of their writer: the triangles are twice the bytes.
void append_vertices(const std::vector<PlacedBlock>& blocks, double h, std::size_t count, std::vector<std::array<float, 3>>& out,
                     PagesAhead& triangle_pages) {
    std::vector<std::array<float, 3>> block(kMaxBlockVertices);
    const double total = double(count);
    for (const PlacedBlock& b : blocks) {
        write_vertices(b, h, block.data());
        out.insert(out.end(), block.data(), block.data() + b.mc->owned.size());
        if (triangle_pages.behind(double(out.size()) / total)) triangle_pages.keep_ahead();
    }
}

/// The triangles of the placed blocks in order, appended to @a out (reserved); their progress
/// is published to @a pages.
void append_triangles(const std::vector<PlacedBlock>& blocks, const std::vector<std::size_t>& first_vertex,
                      std::vector<std::array<std::uint32_t, 3>>& out, PagesAhead& pages) {
    std::vector<std::array<std::uint32_t, 3>> block(kMaxBlockTriangles);
    std::vector<std::uint32_t> borrowed;
    FollowingSweep following(blocks);
    for (std::size_t b = 0; b < blocks.size(); ++b) {
        borrowed_vertices(blocks, following.after(b), first_vertex, b, borrowed);
        write_triangles(*blocks[b].mc, std::uint32_t(first_vertex[b]), borrowed, block.data());
        out.insert(out.end(), block.data(), block.data() + blocks[b].mc->corners.size());
        pages.written(out.size() * sizeof(out[0]));
    }
}

}  // namespace

// The flat mesh: every placed block numbers the vertices it owns from its offset (prefix sums
// over the blocks in origin order) and finds the ones it borrows in the neighbours' cached
// face_index. No table of global edges, no welding afterwards: the same welded mesh for any
// thread count.
//
// The output (730 MB for the 512^3 gyroid) is most of the time, so it is written once: Mesh
// holds std::vectors, whose resize() would zero every element first (serially), so the
// vectors are reserved (on huge pages) and each block's elements appended, computed in a small
// buffer and copied in; appending within the capacity constructs each element once, with its
// value, legally, and the page faults follow the writes. Appending is serial per vector, so
// the vertices and the triangles are written side by side, the vertex writer also taking some
// page faults off the triangle writer (PagesAhead).
Mesh shared_marching_cubes(const SharedTree& tree) {
    McCaches caches;
    caches.parts = false;
    const std::vector<PlacedBlock> blocks = surface_blocks(tree, caches);
    std::vector<std::size_t> first_vertex, first_triangle;
    number_blocks(blocks, first_vertex, first_triangle);
    if (first_vertex.back() > std::numeric_limits<std::uint32_t>::max()) throw Error("shared marching cubes: more than 2^32 vertices");
    Mesh mesh;
    detail::reserve_on_huge_pages(mesh.vertices, first_vertex.back());
    detail::reserve_on_huge_pages(mesh.triangles, first_triangle.back());
    PagesAhead triangle_pages(mesh.triangles.data(), first_triangle.back() * sizeof(mesh.triangles[0]));
    tbb::parallel_invoke([&] { append_vertices(blocks, tree.voxel_size, first_vertex.back(), mesh.vertices, triangle_pages); },
                         [&] { append_triangles(blocks, first_vertex, mesh.triangles, triangle_pages); });
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
