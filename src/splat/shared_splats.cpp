// The splat hierarchy of a shared tree with result matching: each 128^3 node's subtree built
// once per distinct neighbourhood (the node and its 26 neighbours, compared by their shared
// ids), from its 8^3 cells each fitted once per distinct neighbourhood of blocks; placed by
// translation, and the levels above merged over the placed nodes.

#include <openvdb/openvdb.h>

#include <algorithm>
#include <map>
#include <optional>
#include <tuple>

#include "splat/splat_build.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/shared_splats.h"
#include "vdbmesh/shared_tree.h"

namespace vdbmesh {
namespace {

using splat::BuildNode;
using Neighbourhood = std::array<SharedRef, 27>;

/// The level-1 ref at @a origin (a multiple of 128): a node of nodes1, or the tile (of the
/// level-2 node or the root) that stands for it.
SharedRef level1_ref(const SharedTree& tree, const Coord3& origin) {
    const Coord3 top{origin[0] & ~4095, origin[1] & ~4095, origin[2] & ~4095};
    const SharedRef ref = tree.root_ref(top);
    if (is_tile(ref)) return ref;
    const int x = (origin[0] - top[0]) / kNodeVoxels, y = (origin[1] - top[1]) / kNodeVoxels, z = (origin[2] - top[2]) / kNodeVoxels;
    return tree.nodes2[ref].children[(x * 32 + y) * 32 + z];
}

Coord3 offset(const Coord3& origin, int dx, int dy, int dz) {
    return {origin[0] + dx * kNodeVoxels, origin[1] + dy * kNodeVoxels, origin[2] + dz * kNodeVoxels};
}

Neighbourhood neighbourhood(const SharedTree& tree, const Coord3& origin) {
    Neighbourhood refs{};
    int i = 0;
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz) refs[i++] = level1_ref(tree, offset(origin, dx, dy, dz));
    return refs;
}

bool z_major(const Coord3& a, const Coord3& b) { return std::tie(a[2], a[1], a[0]) < std::tie(b[2], b[1], b[0]); }

/// The 128^3 nodes whose cells may hold crossings: those with leaves and the ones just below
/// them on each axis (as build_splat_tree() of a region source), z-major.
std::vector<Coord3> candidate_nodes(const SharedTree& tree) {
    std::vector<Coord3> nodes;
    for (const SharedRootEntry& entry : tree.root) {
        if (is_tile(entry.ref)) continue;
        const SharedNode& n2 = tree.nodes2[entry.ref];
        for (int i = 0; i < 32 * 32 * 32; ++i) {
            if (is_tile(n2.children[i])) continue;
            const Coord3 origin = offset(entry.origin, i >> 10, (i >> 5) & 31, i & 31);
            for (int d = 0; d < 8; ++d) nodes.push_back(offset(origin, -(d & 1), -((d >> 1) & 1), -(d >> 2)));
        }
    }
    std::sort(nodes.begin(), nodes.end(), z_major);
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    return nodes;
}

/// The part of the tree a node's cells read (the node's box from one voxel below to ten
/// beyond: closed cubes, gradients, the cells below the next leaves) as a FloatGrid.
openvdb::FloatGrid::Ptr neighbourhood_grid(const SharedTree& tree, const Coord3& origin) {
    auto grid = openvdb::FloatGrid::create(tree.background);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(tree.voxel_size));
    const auto meets = [&](const Coord3& o, int dim) {
        for (int a = 0; a < 3; ++a)
            if (o[a] + dim - 1 < origin[a] - 1 || o[a] > origin[a] + kNodeVoxels + 9) return false;
        return true;
    };
    const SharedTile& background = tree.tiles[0];
    const auto add_tile = [&](int level, const Coord3& o, SharedRef ref) {
        const SharedTile& tile = tree.tiles[ref & ~kSharedTile];
        if (tile.active == background.active && tile.value == background.value) return;
        grid->tree().addTile(level, openvdb::Coord(o[0], o[1], o[2]), tile.value, tile.active);
    };
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz) {
                const Coord3 o1 = offset(origin, dx, dy, dz);
                if (!meets(o1, kNodeVoxels)) continue;
                const SharedRef r1 = level1_ref(tree, o1);
                if (is_tile(r1)) {
                    add_tile(2, o1, r1);
                    continue;
                }
                const SharedNode& n1 = tree.nodes1[r1];
                for (int j = 0; j < 16 * 16 * 16; ++j) {
                    const Coord3 o0 = {o1[0] + (j >> 8) * 8, o1[1] + ((j >> 4) & 15) * 8, o1[2] + (j & 15) * 8};
                    if (!meets(o0, 8)) continue;
                    const SharedRef r0 = n1.children[j];
                    if (is_tile(r0)) {
                        add_tile(1, o0, r0);
                        continue;
                    }
                    const SharedLeaf& source = tree.leaves[r0];
                    auto* leaf = grid->tree().touchLeaf(openvdb::Coord(o0[0], o0[1], o0[2]));
                    for (int v = 0; v < 512; ++v) leaf->setValueOnly(openvdb::Index(v), source.values[v]);
                    for (int v = 0; v < 512; ++v) leaf->setActiveState(openvdb::Index(v), source.is_active(v));
                }
            }
    return grid;
}

/// The 27 shared refs (leaves or tiles) of the 8^3 blocks around a cell: what its fit reads
/// (its closed cube and one sample beyond, for gradients).
using CellNeighbourhood = std::array<SharedRef, 27>;

/// A node's level-1 refs and its neighbours', and the leaf-level refs of the blocks in them.
class NodeBlocks {
public:
    NodeBlocks(const SharedTree& tree, const Coord3& origin) : tree_(tree), origin_(origin), refs_(neighbourhood(tree, origin)) {}

    /// The ref of the block at @a block (a multiple of 8, within a node of the neighbourhood).
    SharedRef at(const Coord3& block) const {
        int node = 0, index = 0;
        for (int a = 0; a < 3; ++a) {
            const int local = block[a] - origin_[a] + kNodeVoxels;  // 0 .. 3 * 128 - 1
            node = node * 3 + local / kNodeVoxels;
            index = index * 16 + (local % kNodeVoxels) / 8;
        }
        const SharedRef r1 = refs_[node];
        return is_tile(r1) ? r1 : tree_.nodes1[r1].children[index];
    }

    CellNeighbourhood around(const Coord3& cell) const {
        CellNeighbourhood refs{};
        int i = 0;
        for (int dx = -8; dx <= 8; dx += 8)
            for (int dy = -8; dy <= 8; dy += 8)
                for (int dz = -8; dz <= 8; dz += 8) refs[i++] = at({cell[0] + dx, cell[1] + dy, cell[2] + dz});
        return refs;
    }

    /// The cells of the node whose closed cube may hold a crossing (as candidate_cells() of the
    /// node's region): the node's leaves and the cells just below every leaf, z-major.
    std::vector<Coord3> candidate_cells() const {
        std::vector<Coord3> cells;
        for (int x = 0; x <= kNodeVoxels; x += 8)
            for (int y = 0; y <= kNodeVoxels; y += 8)
                for (int z = 0; z <= kNodeVoxels; z += 8) {
                    const Coord3 block{origin_[0] + x, origin_[1] + y, origin_[2] + z};
                    if (is_tile(at(block))) continue;
                    for (int d = 0; d < 8; ++d) {
                        const Coord3 cell{block[0] - (d & 1) * 8, block[1] - ((d >> 1) & 1) * 8, block[2] - (d >> 2) * 8};
                        bool inside = true;
                        for (int a = 0; a < 3; ++a) inside = inside && cell[a] >= origin_[a] && cell[a] < origin_[a] + kNodeVoxels;
                        if (inside) cells.push_back(cell);
                    }
                }
        std::sort(cells.begin(), cells.end(), z_major);
        cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
        return cells;
    }

private:
    const SharedTree& tree_;
    Coord3 origin_;
    Neighbourhood refs_;
};

void translate(splat::CellNodes& cell, const Coord3& by) {
    const auto shift = [&](BuildNode& n) {
        for (int a = 0; a < 3; ++a) {
            n.centre[a] = float(double(n.centre[a]) + by[a]);
            n.origin[a] += by[a];
        }
    };
    for (BuildNode& n : cell.finest) shift(n);
    for (BuildNode& n : cell.middle) shift(n);
    if (cell.leaf) shift(*cell.leaf);
}

/// Result matching at the finer grain: each cell's nodes, relative to its origin, by the
/// blocks it reads (a lattice has few distinct leaves, so its cells repeat within a node too).
using CellCache = std::map<CellNeighbourhood, splat::CellNodes>;

/// A node's subtree fitted at @a origin: its level-6 node relative to the origin (index
/// space) and the subtree breadth-first in world units relative to it; none without crossings.
struct Fitted {
    BuildNode root;
    std::vector<SplatNode> nodes;
};

std::optional<Fitted> fit_node(const SharedTree& tree, const Coord3& origin, const splat::SampleRule& rule, double tolerance,
                               CellCache& cache) {
    const NodeBlocks blocks(tree, origin);
    openvdb::FloatGrid::Ptr region;  // read when a cell is fitted for the first time
    splat::Levels levels(kSplatNodeLevel + 1);
    for (const Coord3& cell : blocks.candidate_cells()) {
        auto [it, added] = cache.try_emplace(blocks.around(cell));
        if (added) {
            if (!region) region = neighbourhood_grid(tree, origin);
            it->second = splat::fit_cell(*region, openvdb::Coord(cell[0], cell[1], cell[2]), rule, tolerance);
            translate(it->second, {-cell[0], -cell[1], -cell[2]});
        }
        splat::CellNodes placed = it->second;
        translate(placed, cell);
        splat::append_cell(levels, placed);
    }
    for (int level = kSplatLeafLevel + 1; level <= kSplatNodeLevel; ++level)
        if (!levels[level - 1].empty()) splat::merge_up(levels, level);
    if (levels[kSplatNodeLevel].empty()) return std::nullopt;
    for (auto& level : levels)
        for (BuildNode& n : level)
            for (int a = 0; a < 3; ++a) {
                n.centre[a] = float(double(n.centre[a]) - origin[a]);
                n.origin[a] -= origin[a];
            }
    const auto transform = openvdb::math::Transform::createLinearTransform(tree.voxel_size);
    Fitted fitted{levels[kSplatNodeLevel][0], splat::breadth_first(levels, kSplatNodeLevel, *transform)};
    return fitted;
}

}  // namespace

std::uint64_t SharedSplatTree::represented_nodes() const {
    std::uint64_t count = first_placed;
    for (const Placed& p : placed) count += subtrees[p.subtree].size();
    return count;
}

SharedSplatTree build_splat_tree(const SharedTree& tree, const SplatOptions& options) {
    SharedSplatTree out;
    out.top.iso = options.iso;
    out.top.inside = options.inside;
    out.top.tolerance = options.coplanar_tolerance;
    // The placed level-6 nodes (their first_child: their index in `placed`), in z-major order.
    splat::Levels levels(kSplatRootLevel + 1);
    std::vector<SharedSplatTree::Placed> placed;
    std::map<Neighbourhood, std::optional<std::uint32_t>> matched;  ///< subtree of a neighbourhood (none: no crossings)
    std::vector<BuildNode> roots;  ///< each subtree's level-6 node, relative to its origin
    CellCache cells;
    // A lattice's grid has no scan box: a cell's samples are its blocks' alone.
    const splat::SampleRule rule = splat::sample_rule(*openvdb::FloatGrid::create(tree.background), options);
    for (const Coord3& origin : candidate_nodes(tree)) {
        auto [it, added] = matched.try_emplace(neighbourhood(tree, origin));
        if (added) {
            if (auto fitted = fit_node(tree, origin, rule, options.coplanar_tolerance, cells)) {
                it->second = std::uint32_t(out.subtrees.size());
                out.subtrees.push_back(std::move(fitted->nodes));
                roots.push_back(fitted->root);
            }
        }
        if (!it->second) continue;
        BuildNode node = roots[*it->second];
        for (int a = 0; a < 3; ++a) {
            node.centre[a] = float(double(node.centre[a]) + origin[a]);
            node.origin[a] += origin[a];
        }
        node.child_count = 0;
        node.first_child = std::uint32_t(placed.size());
        levels[kSplatNodeLevel].push_back(node);
        placed.push_back({*it->second, {origin[0] * tree.voxel_size, origin[1] * tree.voxel_size, origin[2] * tree.voxel_size}});
    }
    for (int level = kSplatNodeLevel + 1; level <= kSplatRootLevel; ++level)
        if (!levels[level - 1].empty()) splat::merge_up(levels, level);
    std::vector<std::pair<int, std::uint32_t>> sources;
    out.top.nodes = splat::breadth_first(levels, kSplatRootLevel, *openvdb::math::Transform::createLinearTransform(tree.voxel_size), &sources);
    // Breadth-first from the root, every level-6 node lies at the same depth: they come last.
    out.first_placed = out.top.nodes.size() - levels[kSplatNodeLevel].size();
    for (std::size_t i = out.first_placed; i < sources.size(); ++i)
        out.placed.push_back(placed[levels[kSplatNodeLevel][sources[i].second].first_child]);
    return out;
}

}  // namespace vdbmesh
