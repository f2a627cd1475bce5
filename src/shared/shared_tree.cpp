// Building the shared tree (hash-consing, Parker and Udeshi section 2) from a per-leaf field or
// a FloatGrid, expanding it back into a FloatGrid, and its statistics.
//
// The build runs top-down to find what must be evaluated and bottom-up to store it:
//  1. positions of each level are enumerated inside the distinct nodes of the level above;
//     known-uniform regions become tiles, and positions with the same periodic key are grouped,
//     the first position (in the sorted walk) of each group standing for all of them;
//  2. the representative leaves are evaluated in parallel, then given ids serially in walk
//     order, a leaf equal (bit for bit) to an earlier one taking its id (hash-consing);
//  3. level-1 and then level-2 nodes are filled with their children's refs in parallel and
//     hash-consed the same way; a node whose children are all one tile becomes that tile.
// Ids therefore follow the walk order, never the thread schedule.

#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <unordered_map>

#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/shared_tree.h"

namespace vdbmesh {

bool LeafField::uniform_region(const Coord3&, int, SharedTile&) const { return false; }
unsigned LeafField::periodic_key(const Coord3&, int, Coord3&) const { return 0; }

SharedRef SharedTree::root_ref(const Coord3& origin) const {
    const auto it = std::lower_bound(root.begin(), root.end(), origin,
                                     [](const SharedRootEntry& e, const Coord3& o) { return e.origin < o; });
    if (it != root.end() && it->origin == origin) return it->ref;
    return tile_ref(0);
}

namespace {

std::uint64_t hash_bytes(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    std::uint64_t h = 1469598103934665603ull;
    for (std::size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

std::uint64_t hash_leaf(const SharedLeaf& leaf) {
    return hash_bytes(leaf.values.data(), sizeof(leaf.values)) * 31 + hash_bytes(leaf.active.data(), sizeof(leaf.active));
}

bool same_leaf(const SharedLeaf& a, const SharedLeaf& b) {
    return std::memcmp(a.values.data(), b.values.data(), sizeof(a.values)) == 0 && a.active == b.active;
}

/// A position's group: its periodic key and axes (0: the position itself).
struct GroupKey {
    Coord3 c;
    unsigned axes;
    bool operator==(const GroupKey& o) const { return c == o.c && axes == o.axes; }
};
struct GroupKeyHash {
    std::size_t operator()(const GroupKey& k) const {
        std::uint64_t h = std::uint64_t(std::uint32_t(k.c[0])) * 0x9e3779b97f4a7c15ull;
        h ^= std::uint64_t(std::uint32_t(k.c[1])) * 0xc2b2ae3d27d4eb4full + (h >> 29);
        h ^= std::uint64_t(std::uint32_t(k.c[2])) * 0x165667b19e3779f9ull + (h >> 31);
        return std::size_t(h ^ (std::uint64_t(k.axes) * 0x5bd1e995));
    }
};

/// What a position of a level holds: a tile known without evaluation, or a group (index into
/// the level's representatives).
struct Slot {
    bool tile = false;
    SharedTile value;
    std::uint32_t group = 0;
};

/// The distinct tiles.
class TileTable {
public:
    explicit TileTable(std::vector<SharedTile>& tiles) : tiles_(tiles) {
        for (std::size_t i = 0; i < tiles_.size(); ++i) index_.emplace(key(tiles_[i]), std::uint32_t(i));
    }
    SharedRef ref(const SharedTile& t) {
        const auto [it, inserted] = index_.emplace(key(t), std::uint32_t(tiles_.size()));
        if (inserted) tiles_.push_back(t);
        return tile_ref(it->second);
    }

private:
    static std::uint64_t key(const SharedTile& t) {
        std::uint32_t bits;
        std::memcpy(&bits, &t.value, 4);
        return (std::uint64_t(bits) << 1) | (t.active ? 1 : 0);
    }
    std::vector<SharedTile>& tiles_;
    std::unordered_map<std::uint64_t, std::uint32_t> index_;
};

bool in_bounds(const Coord3& origin, int dim, const std::array<Coord3, 2>& b) {
    for (int a = 0; a < 3; ++a) {
        if (origin[a] + dim - 1 < b[0][a] || origin[a] > b[1][a]) return false;
    }
    return true;
}

/// The positions of one level and their groups.
struct Level {
    std::vector<Coord3> representatives;  ///< first position of each group, in walk order
    std::unordered_map<GroupKey, std::uint32_t, GroupKeyHash> groups;
    std::vector<SharedRef> refs;  ///< per group, once built

    Slot classify(const LeafField& field, const Coord3& origin, int dim, const std::array<Coord3, 2>& bounds) {
        Slot slot;
        if (!in_bounds(origin, dim, bounds)) {
            slot.tile = true;
            slot.value = {field.background(), false};
            return slot;
        }
        if (field.uniform_region(origin, dim, slot.value)) {
            slot.tile = true;
            return slot;
        }
        GroupKey key{origin, 0};
        key.axes = field.periodic_key(origin, dim, key.c) & 7u;
        if (key.axes == 0) key.c = origin;
        const auto [it, inserted] = groups.emplace(key, std::uint32_t(representatives.size()));
        if (inserted) representatives.push_back(origin);
        slot.group = it->second;
        return slot;
    }
};

int floor_to(int v, int dim) { return int(std::floor(double(v) / dim)) * dim; }

/// Hash-conses internal nodes in order; returns each node's ref.
std::vector<SharedRef> cons_nodes(std::vector<SharedNode>& candidates, std::vector<SharedNode>& table, TileTable& tiles) {
    std::vector<SharedRef> refs(candidates.size());
    std::unordered_multimap<std::uint64_t, std::uint32_t> index;
    for (const SharedNode& n : table) index.emplace(hash_bytes(n.children.data(), n.children.size() * 4), std::uint32_t(&n - table.data()));
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        SharedNode& node = candidates[i];
        const SharedRef first = node.children.front();
        if (is_tile(first) && std::all_of(node.children.begin(), node.children.end(), [&](SharedRef r) { return r == first; })) {
            refs[i] = first;
            continue;
        }
        const std::uint64_t h = hash_bytes(node.children.data(), node.children.size() * 4);
        bool found = false;
        const auto range = index.equal_range(h);
        for (auto it = range.first; it != range.second; ++it) {
            if (table[it->second].children == node.children) {
                refs[i] = it->second;
                found = true;
                break;
            }
        }
        if (!found) {
            refs[i] = SharedRef(table.size());
            index.emplace(h, refs[i]);
            table.push_back(std::move(node));
        }
        (void)tiles;
    }
    return refs;
}

}  // namespace

SharedTree build_shared_tree(const LeafField& field) {
    SharedTree tree;
    tree.voxel_size = field.voxel_size();
    tree.background = field.background();
    tree.tiles.push_back({field.background(), false});
    TileTable tiles(tree.tiles);
    const std::array<Coord3, 2> bounds = field.bounds();

    // 1. Enumerate: level-2 positions covering the bounds, then children of distinct nodes.
    std::vector<Coord3> top;
    for (int x = floor_to(bounds[0][0], 4096); x <= bounds[1][0]; x += 4096)
        for (int y = floor_to(bounds[0][1], 4096); y <= bounds[1][1]; y += 4096)
            for (int z = floor_to(bounds[0][2], 4096); z <= bounds[1][2]; z += 4096) top.push_back({x, y, z});
    Level l2, l1, l0;
    std::vector<Slot> top_slots;
    for (const Coord3& o : top) top_slots.push_back(l2.classify(field, o, 4096, bounds));
    // The children of each representative, in walk order, as candidate nodes: a tile's ref,
    // or (tile bit clear) the index of the child's group, replaced by its ref once built.
    auto enumerate = [&](const Level& parent, Level& child, int child_dim, int n) {
        std::vector<SharedNode> candidates(parent.representatives.size());
        for (std::size_t g = 0; g < parent.representatives.size(); ++g) {
            const Coord3& o = parent.representatives[g];
            auto& children = candidates[g].children;
            children.reserve(std::size_t(n) * n * n);
            for (int x = 0; x < n; ++x)
                for (int y = 0; y < n; ++y)
                    for (int z = 0; z < n; ++z) {
                        const Slot slot = child.classify(field, {o[0] + x * child_dim, o[1] + y * child_dim, o[2] + z * child_dim}, child_dim, bounds);
                        children.push_back(slot.tile ? tiles.ref(slot.value) : slot.group);
                    }
        }
        return candidates;
    };
    std::vector<SharedNode> candidates2 = enumerate(l2, l1, 128, 32);
    std::vector<SharedNode> candidates1 = enumerate(l1, l0, 8, 16);

    // 2. Leaves: evaluated in parallel, a batch at a time (bounded memory), consed in walk order.
    l0.refs.resize(l0.representatives.size());
    {
        std::unordered_multimap<std::uint64_t, std::uint32_t> index;
        constexpr std::size_t kBatch = 1 << 15;
        std::vector<SharedLeaf> evaluated(std::min(kBatch, l0.representatives.size()));
        std::vector<std::uint64_t> hashes(evaluated.size());
        for (std::size_t first = 0; first < l0.representatives.size(); first += kBatch) {
            const std::size_t count = std::min(kBatch, l0.representatives.size() - first);
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 16), [&](const auto& range) {
                for (std::size_t i = range.begin(); i != range.end(); ++i) {
                    field.evaluate(l0.representatives[first + i], evaluated[i]);
                    hashes[i] = hash_leaf(evaluated[i]);
                }
            });
            for (std::size_t i = 0; i < count; ++i) {
                const SharedLeaf& leaf = evaluated[i];
                SharedRef& ref = l0.refs[first + i];
                const float v0 = leaf.values[0];
                const bool all_on = std::all_of(leaf.active.begin(), leaf.active.end(), [](std::uint64_t w) { return w == ~std::uint64_t(0); });
                const bool all_off = std::all_of(leaf.active.begin(), leaf.active.end(), [](std::uint64_t w) { return w == 0; });
                if ((all_on || all_off) &&
                    std::all_of(leaf.values.begin(), leaf.values.end(), [&](float v) { return std::memcmp(&v, &v0, 4) == 0; })) {
                    ref = tiles.ref({v0, all_on});
                    continue;
                }
                bool found = false;
                const auto range = index.equal_range(hashes[i]);
                for (auto it = range.first; it != range.second; ++it) {
                    if (same_leaf(tree.leaves[it->second], leaf)) {
                        ref = it->second;
                        found = true;
                        break;
                    }
                }
                if (!found) {
                    ref = SharedRef(tree.leaves.size());
                    index.emplace(hashes[i], ref);
                    tree.leaves.push_back(leaf);
                }
            }
        }
    }

    // 3. Internal nodes, bottom-up.
    auto build_level = [&](std::vector<SharedNode>& candidates, const Level& child, std::vector<SharedNode>& table) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size()), [&](const auto& range) {
            for (std::size_t g = range.begin(); g != range.end(); ++g) {
                for (SharedRef& r : candidates[g].children) {
                    if (!is_tile(r)) r = child.refs[r];
                }
            }
        });
        return cons_nodes(candidates, table, tiles);
    };
    l1.refs = build_level(candidates1, l0, tree.nodes1);
    candidates1 = {};
    l2.refs = build_level(candidates2, l1, tree.nodes2);
    for (std::size_t i = 0; i < top.size(); ++i) {
        const SharedRef ref = top_slots[i].tile ? tiles.ref(top_slots[i].value) : l2.refs[top_slots[i].group];
        if (ref != tile_ref(0)) tree.root.push_back({top[i], ref});
    }
    std::sort(tree.root.begin(), tree.root.end(), [](const auto& a, const auto& b) { return a.origin < b.origin; });
    return tree;
}

namespace {

using LeafT = openvdb::FloatTree::LeafNodeType;
using Internal1 = openvdb::FloatTree::RootNodeType::ChildNodeType::ChildNodeType;
using Internal2 = openvdb::FloatTree::RootNodeType::ChildNodeType;

/// A FloatGrid seen as a LeafField.
class GridField final : public LeafField {
public:
    explicit GridField(const openvdb::FloatGrid& grid) : grid_(grid) {
        openvdb::CoordBBox box;
        const auto& root = grid.tree().root();
        for (auto it = root.cbeginChildOn(); it; ++it) box.expand(it->getNodeBoundingBox());
        for (auto it = root.cbeginValueAll(); it; ++it) {
            box.expand(openvdb::CoordBBox::createCube(it.getCoord(), 4096));
        }
        if (box.empty()) box = openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(0));
        bounds_ = {Coord3{box.min().x(), box.min().y(), box.min().z()}, Coord3{box.max().x(), box.max().y(), box.max().z()}};
    }
    float background() const override { return grid_.background(); }
    double voxel_size() const override { return grid_.voxelSize()[0]; }
    std::array<Coord3, 2> bounds() const override { return bounds_; }
    void evaluate(const Coord3& origin, SharedLeaf& leaf) const override {
        const openvdb::Coord o(origin[0], origin[1], origin[2]);
        if (const LeafT* node = grid_.tree().probeConstLeaf(o)) {
            for (int i = 0; i < 512; ++i) {
                leaf.values[i] = node->getValue(openvdb::Index(i));
                leaf.set_active(i, node->isValueOn(openvdb::Index(i)));
            }
            return;
        }
        const float v = grid_.tree().getValue(o);
        const bool on = grid_.tree().isValueOn(o);
        leaf.values.fill(v);
        leaf.active.fill(on ? ~std::uint64_t(0) : 0);
    }
    bool uniform_region(const Coord3& origin, int dim, SharedTile& tile) const override {
        const openvdb::Coord o(origin[0], origin[1], origin[2]);
        const auto& tree = grid_.tree();
        bool uniform = false;
        if (dim == 8) uniform = tree.probeConstLeaf(o) == nullptr;
        else if (dim == 128) uniform = tree.probeConstNode<Internal1>(o) == nullptr;
        else uniform = tree.probeConstNode<Internal2>(o) == nullptr;
        if (!uniform) return false;
        tile.value = tree.getValue(o);
        tile.active = tree.isValueOn(o);
        return true;
    }

private:
    const openvdb::FloatGrid& grid_;
    std::array<Coord3, 2> bounds_;
};

}  // namespace

SharedTree build_shared_tree(const openvdb::FloatGrid& grid) {
    const openvdb::math::Transform& t = grid.transform();
    if (!t.isLinear() || !t.hasUniformScale() || t.indexToWorld(openvdb::Vec3d(0)).length() != 0.0) {
        throw UsageError("shared tree: expected a grid with a uniform scale and no translation, got the transform " +
                         t.baseMap()->str());
    }
    SharedTree tree = build_shared_tree(GridField(grid));
    tree.level_set = grid.getGridClass() == openvdb::GRID_LEVEL_SET;
    return tree;
}

std::shared_ptr<openvdb::FloatGrid> to_float_grid(const SharedTree& tree) {
    auto grid = openvdb::FloatGrid::create(tree.background);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(tree.voxel_size));
    if (tree.level_set) grid->setGridClass(openvdb::GRID_LEVEL_SET);
    auto& out = grid->tree();
    const SharedTile& bg = tree.tiles[0];
    auto add_tile = [&](int level, const Coord3& o, SharedRef ref) {
        const SharedTile& t = tree.tiles[ref & ~kSharedTile];
        if (t.active == bg.active && std::memcmp(&t.value, &bg.value, 4) == 0) return;
        out.addTile(level, openvdb::Coord(o[0], o[1], o[2]), t.value, t.active);
    };
    // Leaves to make: (origin, leaf id), collected serially, made in parallel, added serially.
    std::vector<std::pair<Coord3, std::uint32_t>> leaves;
    for (const SharedRootEntry& e : tree.root) {
        if (is_tile(e.ref)) {
            add_tile(3, e.origin, e.ref);
            continue;
        }
        const SharedNode& n2 = tree.nodes2[e.ref];
        for (int i = 0; i < 32 * 32 * 32; ++i) {
            const Coord3 o1 = {e.origin[0] + (i >> 10) * 128, e.origin[1] + ((i >> 5) & 31) * 128, e.origin[2] + (i & 31) * 128};
            const SharedRef r1 = n2.children[i];
            if (is_tile(r1)) {
                add_tile(2, o1, r1);
                continue;
            }
            const SharedNode& n1 = tree.nodes1[r1];
            for (int j = 0; j < 16 * 16 * 16; ++j) {
                const Coord3 o0 = {o1[0] + (j >> 8) * 8, o1[1] + ((j >> 4) & 15) * 8, o1[2] + (j & 15) * 8};
                const SharedRef r0 = n1.children[j];
                if (is_tile(r0)) add_tile(1, o0, r0);
                else leaves.push_back({o0, r0});
            }
        }
    }
    std::vector<LeafT*> made(leaves.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 64), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const Coord3& o = leaves[i].first;
            const SharedLeaf& src = tree.leaves[leaves[i].second];
            auto* leaf = new LeafT(openvdb::Coord(o[0], o[1], o[2]), tree.background);
            for (int v = 0; v < 512; ++v) leaf->setValueOnly(openvdb::Index(v), src.values[v]);
            for (int v = 0; v < 512; ++v) leaf->setActiveState(openvdb::Index(v), src.is_active(v));
            made[i] = leaf;
        }
    });
    for (LeafT* leaf : made) out.addLeaf(leaf);
    return grid;
}

SharedStats shared_stats(const SharedTree& tree) {
    SharedStats s;
    s.stored = {tree.leaves.size(), tree.nodes1.size(), tree.nodes2.size()};
    s.tiles = tree.tiles.size();
    s.root_entries = tree.root.size();
    // Per distinct node: how many nodes of each level lie under it, and its active voxels.
    std::vector<std::uint64_t> leaf_active(tree.leaves.size());
    for (std::size_t i = 0; i < tree.leaves.size(); ++i) {
        for (std::uint64_t w : tree.leaves[i].active) leaf_active[i] += std::uint64_t(__builtin_popcountll(w));
    }
    auto tile_active = [&](SharedRef r, std::uint64_t voxels) { return tree.tiles[r & ~kSharedTile].active ? voxels : 0; };
    struct Under {
        std::uint64_t leaves = 0, nodes1 = 0, active = 0;
    };
    std::vector<Under> under1(tree.nodes1.size()), under2(tree.nodes2.size());
    for (std::size_t i = 0; i < tree.nodes1.size(); ++i) {
        for (SharedRef r : tree.nodes1[i].children) {
            if (is_tile(r)) under1[i].active += tile_active(r, 512);
            else {
                under1[i].leaves += 1;
                under1[i].active += leaf_active[r];
            }
        }
    }
    for (std::size_t i = 0; i < tree.nodes2.size(); ++i) {
        for (SharedRef r : tree.nodes2[i].children) {
            if (is_tile(r)) under2[i].active += tile_active(r, 128ull * 128 * 128);
            else {
                under2[i].nodes1 += 1;
                under2[i].leaves += under1[r].leaves;
                under2[i].active += under1[r].active;
            }
        }
    }
    for (const SharedRootEntry& e : tree.root) {
        if (is_tile(e.ref)) {
            s.active_voxels += tile_active(e.ref, 4096ull * 4096 * 4096);
            continue;
        }
        s.represented[2] += 1;
        s.represented[1] += under2[e.ref].nodes1;
        s.represented[0] += under2[e.ref].leaves;
        s.active_voxels += under2[e.ref].active;
    }
    const std::uint64_t leaf_bytes = sizeof(SharedLeaf), n1_bytes = 4096 * 4, n2_bytes = 32768 * 4;
    s.shared_bytes = s.stored[0] * leaf_bytes + s.stored[1] * n1_bytes + s.stored[2] * n2_bytes + s.tiles * sizeof(SharedTile) +
                     s.root_entries * sizeof(SharedRootEntry);
    // OpenVDB: a leaf holds 512 floats and two masks; internal nodes a union table and two masks.
    s.expanded_bytes = s.represented[0] * (512 * 4 + 2 * 64) + s.represented[1] * (4096 * 8 + 2 * 512) +
                       s.represented[2] * (32768 * 8 + 2 * 4096);
    return s;
}

}  // namespace vdbmesh
