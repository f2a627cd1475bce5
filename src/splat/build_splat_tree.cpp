// The splat tree of a grid: the 8^3 cells fitted in parallel (splat_cell.cpp), merged level by
// level up to the 4096^3 nodes and the root, then laid out breadth-first in world space.

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <future>
#include <optional>
#include <tuple>
#include <utility>

#include "splat/splat_build.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"

namespace vdbmesh::splat {
namespace {

constexpr int kCell = 8;

bool z_major(const openvdb::Coord& a, const openvdb::Coord& b) {
    return std::make_tuple(a.z(), a.y(), a.x()) < std::make_tuple(b.z(), b.y(), b.x());
}

}  // namespace

namespace {

/// Which sides of the isovalue a block's samples lie on (bits).
constexpr std::uint8_t kInsideSide = 1, kOutsideSide = 2;

std::uint8_t sides_of(const float* values, std::size_t count, const SampleRule& rule) {
    std::uint8_t sides = 0;
    for (std::size_t i = 0; i < count; ++i)
        sides |= (rule.inside_above ? values[i] > rule.iso : values[i] < rule.iso) ? kInsideSide : kOutsideSide;
    return sides;
}

/// The 8^3 blocks a cell's closed cube reaches: its own and those one block above on each
/// axis; block d lies at the cell's origin plus 8 * (d & 1, d >> 1 & 1, d >> 2).
openvdb::Coord block_offset(int d) { return openvdb::Coord((d & 1) * kCell, (d >> 1 & 1) * kCell, (d >> 2) * kCell); }

/// A cell reached by a leaf: the sides of the leaves that reach it, and which of its blocks
/// (bit d) they are.
struct ReachedCell {
    openvdb::Coord cell;
    std::uint8_t sides = 0;
    std::uint8_t leaves = 0;
};

/// Whether a cell's closed cube may hold a crossed edge: its blocks' samples (a leaf's, or a
/// tile's value where there is no leaf) lie on both sides, or some of its samples lie
/// outside the scan box (they are outside whatever their value).
bool may_cross(const ReachedCell& reached, const openvdb::FloatGrid::ConstAccessor& accessor, const SampleRule& rule) {
    if (rule.scan_box && !rule.scan_box->isInside(openvdb::CoordBBox(reached.cell, reached.cell.offsetBy(kCell)))) return true;
    std::uint8_t sides = reached.sides;
    for (int d = 0; d < 8 && sides != (kInsideSide | kOutsideSide); ++d)
        if (!(reached.leaves >> d & 1)) {
            const float tile = accessor.getValue(reached.cell + block_offset(d));
            sides |= sides_of(&tile, 1, rule);
        }
    return sides == (kInsideSide | kOutsideSide);
}

}  // namespace

/// The leaves, and the cells just below them on each axis (their cube reaches the leaf's first
/// samples); of those, the ones whose blocks' samples lie on both sides (a leaf's sides are
/// found in one pass over its values: most cells reached by a leaf hold no crossing).
std::vector<openvdb::Coord> candidate_cells(const openvdb::FloatGrid& grid, const std::optional<openvdb::CoordBBox>& within,
                                            const SampleRule& rule) {
    std::vector<const openvdb::FloatTree::LeafNodeType*> leaves;
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) leaves.push_back(leaf.getLeaf());
    std::vector<ReachedCell> reached(leaves.size() * 8);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size()), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const auto& leaf = *leaves[i];
            const std::uint8_t sides = sides_of(leaf.buffer().data(), leaf.SIZE, rule);  // loads a delayed leaf once
            for (int d = 0; d < 8; ++d) reached[i * 8 + d] = {leaf.origin() - block_offset(d), sides, std::uint8_t(1 << d)};
        }
    });
    tbb::parallel_sort(reached.begin(), reached.end(), [](const ReachedCell& a, const ReachedCell& b) { return z_major(a.cell, b.cell); });
    // The same cell reached by several leaves: one entry, their sides and blocks joined.
    std::size_t merged = 0;
    for (std::size_t i = 0; i < reached.size(); ++merged) {
        ReachedCell cell = reached[i];
        for (++i; i < reached.size() && reached[i].cell == cell.cell; ++i) {
            cell.sides |= reached[i].sides;
            cell.leaves |= reached[i].leaves;
        }
        reached[merged] = cell;
    }
    reached.resize(merged);
    std::vector<std::uint8_t> keep(reached.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, reached.size()), [&](const auto& range) {
        const auto accessor = grid.getConstAccessor();
        for (std::size_t i = range.begin(); i != range.end(); ++i)
            keep[i] = (!within || within->isInside(reached[i].cell)) && may_cross(reached[i], accessor, rule);
    });
    std::vector<openvdb::Coord> cells;
    for (std::size_t i = 0; i < reached.size(); ++i)
        if (keep[i]) cells.push_back(reached[i].cell);
    return cells;
}

namespace {

/// Cells fitted at a time: their nodes are appended to the levels before the next are fitted,
/// so that only the levels grow with the grid.
constexpr std::size_t kCellsAtATime = 1 << 14;

/// The origin of the level-@a level cube holding @a origin.
std::array<std::int32_t, 3> parent_origin(const std::array<std::int32_t, 3>& origin, int level) {
    const std::int32_t mask = ~((std::int32_t(2) << level) - 1);
    return {origin[0] & mask, origin[1] & mask, origin[2] & mask};
}

}  // namespace

/// A chunk of cells at a time; their nodes in the cells' order. The order of level 2 does not
/// matter (merge_up() sorts it by position), so nor does that of @a cells.
void append_cells(Levels& levels, const openvdb::FloatGrid& grid, const std::vector<openvdb::Coord>& cells,
                  const SampleRule& rule, double tolerance) {
    // Kept from chunk to chunk: a cell's vectors, once grown, hold the next chunk's cell too.
    std::vector<CellNodes> fitted(std::min(cells.size(), kCellsAtATime));
    for (std::size_t begin = 0; begin < cells.size(); begin += kCellsAtATime) {
        const std::size_t end = std::min(cells.size(), begin + kCellsAtATime);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, 64), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) fit_cell(grid, cells[i], rule, tolerance, fitted[i - begin]);
        });
        for (std::size_t i = 0; i < end - begin; ++i) append_cell(levels, fitted[i]);
    }
}

void append_cell(Levels& levels, CellNodes& cell) {
    if (!cell.leaf) return;
    const auto finest_offset = std::uint32_t(levels[0].size()), middle_offset = std::uint32_t(levels[1].size());
    for (BuildNode& n : cell.middle) n.first_child += finest_offset;
    if (cell.leaf->child_count != 0) cell.leaf->first_child += middle_offset;
    levels[0].insert(levels[0].end(), cell.finest.begin(), cell.finest.end());
    levels[1].insert(levels[1].end(), cell.middle.begin(), cell.middle.end());
    levels[2].push_back(*cell.leaf);
}

/// By parent, then z-major.
void merge_up(Levels& levels, int level, bool unsigned_normals) {
    std::vector<BuildNode>& below = levels[level - 1];
    const bool root = level == kSplatRootLevel;
    const auto key = [&](const BuildNode& n) {
        const auto p = root ? std::array<std::int32_t, 3>{} : parent_origin(n.origin, level);
        return std::make_tuple(p[2], p[1], p[0], n.origin[2], n.origin[1], n.origin[0]);
    };
    // Every node of a level has its own cube: any sort gives the same order.
    tbb::parallel_sort(below.begin(), below.end(), [&](const BuildNode& a, const BuildNode& b) { return key(a) < key(b); });
    for (std::size_t begin = 0; begin < below.size();) {
        const auto origin = root ? std::array<std::int32_t, 3>{} : parent_origin(below[begin].origin, level);
        std::size_t end = begin + 1;
        while (end < below.size() && (root || parent_origin(below[end].origin, level) == origin)) ++end;
        if (unsigned_normals) align_normals(&below[begin], std::uint32_t(end - begin));
        BuildNode parent = merge_children(&below[begin], std::uint32_t(end - begin), origin);
        parent.first_child = std::uint32_t(begin);
        levels[level].push_back(parent);
        begin = end;
    }
}

namespace {

/// The node in the grid's world space (normals by the inverse transpose of the index-to-world
/// map; radii by its largest voxel edge).
SplatNode to_world(const BuildNode& n, const openvdb::math::Transform& transform, double voxel, std::uint8_t level) {
    const openvdb::Vec3d centre = transform.indexToWorld(openvdb::Vec3d(n.centre[0], n.centre[1], n.centre[2]));
    openvdb::Vec3d normal = transform.baseMap()->applyIJT(openvdb::Vec3d(n.normal[0], n.normal[1], n.normal[2]));
    normal.normalize();
    SplatNode out;
    out.centre = {float(centre.x()), float(centre.y()), float(centre.z())};
    out.normal = {float(normal.x()), float(normal.y()), float(normal.z())};
    out.radius = static_cast<float>(n.radius * voxel);
    out.cone = n.cone;
    out.weight = n.weight;
    out.level = level;
    return out;
}

}  // namespace

std::vector<SplatNode> breadth_first(const Levels& levels, int top, const openvdb::math::Transform& transform,
                                     std::vector<std::pair<int, std::uint32_t>>* sources) {
    if (levels[top].empty()) return {};
    // The order first (each node's level and index, and where its children start), then the
    // nodes in world space, in parallel.
    std::vector<std::pair<int, std::uint32_t>> order{{top, 0}};
    std::vector<std::uint32_t> first_child;
    for (std::size_t out = 0; out < order.size(); ++out) {
        const auto [level, index] = order[out];
        const BuildNode& n = levels[level][index];
        first_child.push_back(std::uint32_t(order.size()));
        for (std::uint32_t c = 0; c < n.child_count; ++c) order.emplace_back(level - 1, n.first_child + c);
    }
    const openvdb::Vec3d voxel_size = transform.voxelSize();
    const double voxel = std::max({voxel_size.x(), voxel_size.y(), voxel_size.z()});
    std::vector<SplatNode> nodes(order.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size()), [&](const auto& range) {
        for (std::size_t out = range.begin(); out != range.end(); ++out) {
            const auto [level, index] = order[out];
            const BuildNode& n = levels[level][index];
            nodes[out] = to_world(n, transform, voxel, std::uint8_t(level));
            nodes[out].first_child = first_child[out];
            nodes[out].child_count = n.child_count;
        }
    });
    if (sources) *sources = std::move(order);
    return nodes;
}

}  // namespace vdbmesh::splat

namespace vdbmesh {

std::size_t SplatTree::leaf_count() const {
    return std::size_t(std::count_if(nodes.begin(), nodes.end(), [](const SplatNode& n) { return n.child_count == 0; }));
}

namespace splat {

SampleRule sample_rule(const openvdb::FloatGrid& grid, const SplatOptions& options) {
    if (!(options.coplanar_tolerance >= 0))
        throw UsageError("splat tolerance: expected >= 0 voxels, got " + std::to_string(options.coplanar_tolerance));
    SampleRule rule;
    rule.iso = options.iso;
    rule.inside_above = options.inside == Inside::above;
    rule.scan_box = stored_scan_box(grid);
    return rule;
}

SplatTree assemble(Levels& levels, const openvdb::math::Transform& transform, const SplatOptions& options,
                   bool unsigned_normals, LevelPruning* pruning) {
    for (int level = kSplatLeafLevel + 1; level <= kSplatRootLevel; ++level)
        if (!levels[level - 1].empty()) merge_up(levels, level, unsigned_normals);
    SplatTree tree;
    if (pruning) {
        pruning->fit(levels);  // the levels above leaf level counted too, before the layout
        tree.finest_kept = std::uint8_t(pruning->finest_kept());
    }
    tree.nodes = breadth_first(levels, kSplatRootLevel, transform);
    tree.iso = options.iso;
    tree.inside = options.inside;
    tree.tolerance = options.coplanar_tolerance;
    return tree;
}

namespace {

/// The 128^3 nodes whose cells may hold crossings: those holding active values and the ones
/// just below them on each axis (their cells reach the first samples of the node above).
std::vector<openvdb::Coord> candidate_nodes(const GridRegionSource& source) {
    std::vector<openvdb::Coord> nodes;
    for (const NodeWeight& node : source.nodes())
        for (int dz = 0; dz <= 1; ++dz)
            for (int dy = 0; dy <= 1; ++dy)
                for (int dx = 0; dx <= 1; ++dx)
                    nodes.push_back(openvdb::Coord(node.origin[0] - dx * kNodeVoxels, node.origin[1] - dy * kNodeVoxels,
                                                   node.origin[2] - dz * kNodeVoxels));
    std::sort(nodes.begin(), nodes.end(), z_major);
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    return nodes;
}

/// What a node's cells read: their closed cubes and one sample beyond for gradients (the
/// samples of node - 1 to node + 129 on each axis), which holds the leaves just above whose
/// cells below lie in the node.
IndexBox node_region(const openvdb::Coord& node) {
    IndexBox box;
    for (int a = 0; a < 3; ++a) {
        box.min[a] = node[a] - 1;
        box.max[a] = node[a] + kNodeVoxels + 2;
    }
    return box;
}

}  // namespace
}  // namespace splat

SplatTree build_splat_tree(const openvdb::FloatGrid& grid, const SplatOptions& options) {
    const splat::SampleRule rule = splat::sample_rule(grid, options);
    splat::Levels levels(kSplatRootLevel + 1);
    splat::append_cells(levels, grid, splat::candidate_cells(grid, std::nullopt, rule), rule, options.coplanar_tolerance);
    return splat::assemble(levels, grid.transform(), options);
}

SplatTree build_splat_tree(const GridRegionSource& source, const SplatOptions& options) {
    const auto description = source.description();
    const splat::SampleRule rule = splat::sample_rule(*description, options);
    // One node at a time (its cells fitted in parallel), the next node's region read
    // meanwhile (reading waits on the file and the decoding children, fitting on the cores).
    splat::Levels levels(kSplatRootLevel + 1);
    splat::LevelPruning pruning(options.max_bytes);
    const std::vector<openvdb::Coord> nodes = splat::candidate_nodes(source);
    const auto read_async = [&source](const openvdb::Coord& node) {
        return std::async(std::launch::async, [&source, node] { return source.read(splat::node_region(node)); });
    };
    std::future<std::shared_ptr<openvdb::FloatGrid>> next;
    if (!nodes.empty()) next = read_async(nodes.front());
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const auto region = next.get();
        if (i + 1 < nodes.size()) next = read_async(nodes[i + 1]);
        const openvdb::CoordBBox cells_box(nodes[i], nodes[i].offsetBy(kNodeVoxels - 1));
        splat::append_cells(levels, *region, splat::candidate_cells(*region, cells_box, rule), rule, options.coplanar_tolerance);
        pruning.fit(levels);
    }
    return splat::assemble(levels, description->transform(), options, false, &pruning);
}

}  // namespace vdbmesh
