// Connected components (6-connected voxels with value < 0) on the shared tree, after section 6
// of Parker and Udeshi: each distinct node is labelled once, its children's labels merged
// across the faces between them; what crosses a face between two nodes is itself a result
// cached under (level, the two ids, the axis), computed from the faces of their children.
// Tiles take part as nodes whose every child is the tile itself (one label when inside).
//
// The plain reference labels runs of inside voxels along z, line by line (run_labels.h).

#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "shared/result_cache.h"
#include "shared/run_labels.h"
#include "vdbmesh/union_find.h"
#include "vdbmesh/error.h"
#include "vdbmesh/shared_tree.h"

namespace vdbmesh {

namespace {

using detail::UnionFind;

using Pairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

struct NodeLabels {
    std::uint32_t count = 0;
    std::vector<std::uint32_t> offset;  ///< per child: first element in map
    std::vector<std::uint32_t> map;     ///< child-local label -> node label
};

class Components {
public:
    explicit Components(const SharedTree& tree) : tree_(tree) {}

    std::uint64_t run() {
        // Leaves.
        leaf_labels_.resize(tree_.leaves.size());
        leaf_count_.resize(tree_.leaves.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tree_.leaves.size(), 16), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) label_leaf(i);
        });
        labels1_.resize(tree_.nodes1.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tree_.nodes1.size(), 1), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) labels1_[i] = label_node(1, tree_.nodes1[i]);
        });
        labels2_.resize(tree_.nodes2.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tree_.nodes2.size(), 1), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) labels2_[i] = label_node(2, tree_.nodes2[i]);
        });
        // Root entries and the faces between them.
        const auto& root = tree_.root;
        std::vector<std::uint32_t> offset(root.size() + 1, 0);
        for (std::size_t i = 0; i < root.size(); ++i) offset[i + 1] = offset[i] + count(3, root[i].ref);
        UnionFind uf(offset.back());
        for (std::size_t i = 0; i < root.size(); ++i) {
            for (int axis = 0; axis < 3; ++axis) {
                Coord3 next = root[i].origin;
                next[axis] += 4096;
                const auto it = std::lower_bound(root.begin(), root.end(), next, [](const SharedRootEntry& e, const Coord3& o) { return e.origin < o; });
                if (it == root.end() || it->origin != next) continue;
                const std::size_t j = std::size_t(it - root.begin());
                for (const auto& [a, b] : pairs(3, root[i].ref, root[j].ref, axis)) uf.unite(offset[i] + a, offset[j] + b);
            }
        }
        std::uint32_t n = 0;
        uf.labels(n);
        return n;
    }

private:
    bool tile_inside(SharedRef r) const { return tree_.tiles[r & ~kSharedTile].value < 0; }

    /// Labels of a ref at @a level (0 leaf, 1, 2 node, 3 a root entry: a level-2 ref).
    std::uint32_t count(int level, SharedRef r) const {
        if (is_tile(r)) return tile_inside(r) ? 1 : 0;
        if (level == 0) return leaf_count_[r];
        return level == 1 ? labels1_[r].count : labels2_[r].count;
    }

    void label_leaf(std::size_t id) {
        const SharedLeaf& leaf = tree_.leaves[id];
        UnionFind uf(512);
        for (int x = 0; x < 8; ++x)
            for (int y = 0; y < 8; ++y)
                for (int z = 0; z < 8; ++z) {
                    const int i = (x * 8 + y) * 8 + z;
                    if (!(leaf.values[i] < 0)) continue;
                    if (x < 7 && leaf.values[i + 64] < 0) uf.unite(i, i + 64);
                    if (y < 7 && leaf.values[i + 8] < 0) uf.unite(i, i + 8);
                    if (z < 7 && leaf.values[i + 1] < 0) uf.unite(i, i + 1);
                }
        // Number only the inside voxels' components, in voxel order.
        std::array<std::int16_t, 512> label;
        label.fill(-1);
        std::array<std::int16_t, 512> of_root;
        of_root.fill(-1);
        std::int16_t n = 0;
        for (int i = 0; i < 512; ++i) {
            if (!(leaf.values[i] < 0)) continue;
            const std::uint32_t r = uf.find(std::uint32_t(i));
            if (of_root[r] < 0) of_root[r] = n++;
            label[i] = of_root[r];
        }
        leaf_labels_[id] = label;
        leaf_count_[id] = std::uint32_t(n);
    }

    /// The child @a index of a ref at @a level (a tile's children are the tile).
    SharedRef child(int level, SharedRef r, int index) const {
        if (is_tile(r)) return r;
        return level == 1 ? tree_.nodes1[r].children[index] : tree_.nodes2[r].children[index];
    }
    /// Node label of child @a index's label @a l.
    std::uint32_t map(int level, SharedRef r, int index, std::uint32_t l) const {
        if (is_tile(r)) return 0;
        const NodeLabels& n = level == 1 ? labels1_[r] : labels2_[r];
        return n.map[n.offset[index] + l];
    }

    NodeLabels label_node(int level, const SharedNode& node) {
        const int n = kSharedChildren[level];
        NodeLabels out;
        out.offset.resize(node.children.size() + 1);
        for (std::size_t c = 0; c < node.children.size(); ++c) out.offset[c + 1] = out.offset[c] + count(level - 1, node.children[c]);
        UnionFind uf(out.offset.back());
        for (int x = 0; x < n; ++x)
            for (int y = 0; y < n; ++y)
                for (int z = 0; z < n; ++z) {
                    const int c = (x * n + y) * n + z;
                    const int next[3] = {x + 1 < n ? c + n * n : -1, y + 1 < n ? c + n : -1, z + 1 < n ? c + 1 : -1};
                    for (int axis = 0; axis < 3; ++axis) {
                        if (next[axis] < 0) continue;
                        const SharedRef a = node.children[c], b = node.children[next[axis]];
                        if (count(level - 1, a) == 0 || count(level - 1, b) == 0) continue;
                        for (const auto& [la, lb] : pairs(level - 1, a, b, axis)) uf.unite(out.offset[c] + la, out.offset[next[axis]] + lb);
                    }
                }
        out.map = uf.labels(out.count);
        return out;
    }

    /// Which labels of @a a touch which of @a b across the face where b follows a along @a axis.
    const Pairs& pairs(int level, SharedRef a, SharedRef b, int axis) {
        return cache_.get({std::uint32_t(level), a, b, std::uint32_t(axis)}, [&] {
            Pairs out;
            if (count(level == 3 ? 3 : level, a) == 0 || count(level == 3 ? 3 : level, b) == 0) return out;
            if (is_tile(a) && is_tile(b)) {
                out.push_back({0, 0});
                return out;
            }
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            if (level == 0) {
                for (int i = 0; i < 8; ++i)
                    for (int j = 0; j < 8; ++j) {
                        int pa[3], pb[3];
                        pa[axis] = 7;
                        pb[axis] = 0;
                        pa[u] = pb[u] = i;
                        pa[v] = pb[v] = j;
                        const int la = leaf_label(a, (pa[0] * 8 + pa[1]) * 8 + pa[2]);
                        const int lb = leaf_label(b, (pb[0] * 8 + pb[1]) * 8 + pb[2]);
                        if (la >= 0 && lb >= 0) out.push_back({std::uint32_t(la), std::uint32_t(lb)});
                    }
            } else {
                const int node_level = level == 3 ? 2 : level;
                const int n = kSharedChildren[node_level];
                for (int i = 0; i < n; ++i)
                    for (int j = 0; j < n; ++j) {
                        int pa[3], pb[3];
                        pa[axis] = n - 1;
                        pb[axis] = 0;
                        pa[u] = pb[u] = i;
                        pa[v] = pb[v] = j;
                        const int ia = (pa[0] * n + pa[1]) * n + pa[2], ib = (pb[0] * n + pb[1]) * n + pb[2];
                        const SharedRef ca = child(node_level, a, ia), cb = child(node_level, b, ib);
                        if (count(node_level - 1, ca) == 0 || count(node_level - 1, cb) == 0) continue;
                        for (const auto& [la, lb] : pairs(node_level - 1, ca, cb, axis)) {
                            out.push_back({map(node_level, a, ia, la), map(node_level, b, ib, lb)});
                        }
                    }
            }
            std::sort(out.begin(), out.end());
            out.erase(std::unique(out.begin(), out.end()), out.end());
            return out;
        });
    }

    int leaf_label(SharedRef r, int voxel) const {
        if (is_tile(r)) return tile_inside(r) ? 0 : -1;
        return leaf_labels_[r][voxel];
    }

    const SharedTree& tree_;
    std::vector<std::array<std::int16_t, 512>> leaf_labels_;
    std::vector<std::uint32_t> leaf_count_;
    std::vector<NodeLabels> labels1_, labels2_;
    detail::ResultCache<4, Pairs> cache_;
};

}  // namespace

std::uint64_t shared_components(const SharedTree& tree) { return Components(tree).run(); }

std::uint64_t plain_components(const openvdb::FloatGrid& grid, const std::array<Coord3, 2>& box, bool periodic) {
    const auto runs = detail::collect_runs(box[1][0] - box[0][0] + 1, box[1][1] - box[0][1] + 1, box[1][2] - box[0][2] + 1, [&] {
        return [&box, accessor = grid.getConstAccessor()](int x, int y, int z) mutable {
            return accessor.getValue(openvdb::Coord(box[0][0] + x, box[0][1] + y, box[0][2] + z)) < 0;
        };
    });
    return detail::label_runs(runs, periodic).count;
}

std::uint64_t plain_components(const openvdb::FloatGrid& grid) {
    // The extent of what can be inside: the leaves and the inside tiles.
    openvdb::CoordBBox box;
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) box.expand(leaf->getNodeBoundingBox());
    auto tile = grid.tree().cbeginValueAll();
    tile.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);
    for (; tile; ++tile) {
        if (*tile < 0) box.expand(tile.getBoundingBox());
    }
    if (box.empty()) return 0;
    return plain_components(grid, {Coord3{box.min().x(), box.min().y(), box.min().z()}, Coord3{box.max().x(), box.max().y(), box.max().z()}},
                            false);
}

}  // namespace vdbmesh
