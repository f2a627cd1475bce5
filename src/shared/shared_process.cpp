// Process simulation on the shared tree (Parker and Udeshi, section 4): conformal deposition
// (a dilation), directional etching down to a stop layer (an erosion along an axis) and CSG
// with another grid, each a map from a node and its 26 neighbours to a new node. The result of
// a neighbourhood is cached under the 27 ids (and the id of what the other grid holds there,
// when that is one tile), so a periodic input is computed once per distinct neighbourhood; the
// output is hash-consed into a new shared tree in a fixed walk order.
//
// Rules (narrow-band level sets, background b, voxel h; per voxel, the same in the plain
// references below, which walk the expanded grid):
//  - deposit r: v'(x) = min over offsets d, |d| <= r + h, of (v(x + d) + |d|) - r, where a
//    sample equal to +b (beyond the band) counts as +infinity; clamped to [-b, b].
//  - etch e along +axis (or -axis): v'(x) = max of v(x + s a) over s = 0, h, ..., e, the walk
//    stopping before the first sample inside the stop layer (value < 0); x itself inside the
//    stop layer keeps v(x).
//  - csg: union min(v, w), intersection max(v, w), difference max(v, -w).

#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>

#include "shared/result_cache.h"
#include "vdbmesh/error.h"
#include "vdbmesh/shared_process.h"

namespace vdbmesh {

namespace {

using Key27 = std::array<SharedRef, 27>;
constexpr std::uint32_t kNoContext = ~0u;
constexpr int kS = 24;  // samples of a leaf's neighbourhood per axis: the leaf and 8 on each side

/// The per-voxel rule of an operation, applied to a sample accessor get(dx, dy, dz) relative to
/// the voxel (|d| <= 8 per axis), and to the other grid's value at the voxel.
struct VoxelRule {
    /// @a s: the 24^3 samples around the leaf (kS per axis, the leaf at 8..15), @a i: the voxel's
    /// index in them; @a other(dx, dy, dz): the other grid at the voxel plus an offset.
    std::function<float(const float* s, int i, const std::function<float(int, int, int)>& other)> apply;
    bool uses_other = false;
    /// The output of a tile whose neighbourhood is all that tile (and the other grid a tile).
    std::function<float(float v, float w)> tile;
};

struct Offset {
    int d[3];
    int delta;  ///< in the 24^3 samples
    double length;
};

constexpr int sample_delta(int dx, int dy, int dz) { return (dx * kS + dy) * kS + dz; }

std::vector<Offset> ball_offsets(double radius_voxels) {
    std::vector<Offset> out;
    const int r = int(std::ceil(radius_voxels));
    for (int x = -r; x <= r; ++x)
        for (int y = -r; y <= r; ++y)
            for (int z = -r; z <= r; ++z) {
                const double l = std::sqrt(double(x * x + y * y + z * z));
                if (l <= radius_voxels + 1e-9) out.push_back({{x, y, z}, sample_delta(x, y, z), l});
            }
    return out;
}

float clamp_band(double v, float bg) { return float(std::clamp(v, double(-bg), double(bg))); }

VoxelRule deposit_rule(double distance, double h, float bg) {
    auto offsets = std::make_shared<std::vector<Offset>>(ball_offsets(distance / h + 1.0));
    VoxelRule rule;
    rule.apply = [offsets, distance, h, bg](const float* s, int i, const auto&) {
        double best = std::numeric_limits<double>::infinity();
        for (const Offset& o : *offsets) {
            const float v = s[i + o.delta];
            if (v >= bg) continue;
            best = std::min(best, double(v) + o.length * h);
        }
        return clamp_band(best - distance, bg);
    };
    rule.tile = [distance, bg](float v, float) { return v >= bg ? bg : clamp_band(double(v) - distance, bg); };
    return rule;
}

VoxelRule etch_rule(int axis, int sign, int steps, bool with_stop) {
    VoxelRule rule;
    rule.uses_other = with_stop;
    rule.apply = [axis, sign, steps, with_stop](const float* samples, int i, const auto& stop) {
        float v = samples[i];
        if (with_stop && stop(0, 0, 0) < 0) return v;
        for (int s = 1; s <= steps; ++s) {
            int d[3] = {0, 0, 0};
            d[axis] = sign * s;
            if (with_stop && stop(d[0], d[1], d[2]) < 0) break;
            v = std::max(v, samples[i + sample_delta(d[0], d[1], d[2])]);
        }
        return v;
    };
    rule.tile = [](float v, float) { return v; };
    return rule;
}

VoxelRule csg_rule(CsgOp op) {
    VoxelRule rule;
    rule.uses_other = true;
    auto combine = [op](float v, float w) {
        switch (op) {
            case CsgOp::unite: return std::min(v, w);
            case CsgOp::intersect: return std::max(v, w);
            case CsgOp::subtract: return std::max(v, -w);
        }
        return v;
    };
    rule.apply = [combine](const float* samples, int i, const auto& other) { return combine(samples[i], other(0, 0, 0)); };
    rule.tile = combine;
    return rule;
}

bool is_background(float v, bool active, float bg) { return !active && std::memcmp(&v, &bg, 4) == 0; }

/// Output value and state of one voxel: active strictly inside the band.
void store(SharedLeaf& leaf, int n, float v, float bg) {
    const bool active = v > -bg && v < bg;
    leaf.values[n] = active ? v : (v > 0 ? bg : -bg);
    leaf.set_active(n, active);
}

/// Hash-consing into a new tree, serially.
class Conser {
public:
    explicit Conser(SharedTree& out) : out_(out) {}
    SharedRef tile(float v, bool active) {
        std::uint32_t bits;
        std::memcpy(&bits, &v, 4);
        const std::uint64_t key = (std::uint64_t(bits) << 1) | (active ? 1 : 0);
        const auto [it, inserted] = tiles_.emplace(key, std::uint32_t(out_.tiles.size()));
        if (inserted) out_.tiles.push_back({v, active});
        return tile_ref(it->second);
    }
    SharedRef leaf(const SharedLeaf& leaf) {
        const float v0 = leaf.values[0];
        const bool all_on = std::all_of(leaf.active.begin(), leaf.active.end(), [](std::uint64_t w) { return w == ~std::uint64_t(0); });
        const bool all_off = std::all_of(leaf.active.begin(), leaf.active.end(), [](std::uint64_t w) { return w == 0; });
        if ((all_on || all_off) && std::all_of(leaf.values.begin(), leaf.values.end(), [&](float v) { return std::memcmp(&v, &v0, 4) == 0; })) {
            return tile(v0, all_on);
        }
        std::string bytes(reinterpret_cast<const char*>(&leaf), sizeof(SharedLeaf));
        const auto [it, inserted] = leaves_.emplace(std::move(bytes), std::uint32_t(out_.leaves.size()));
        if (inserted) out_.leaves.push_back(leaf);
        return it->second;
    }
    SharedRef node(int level, std::vector<SharedRef> children) {
        const SharedRef first = children.front();
        if (is_tile(first) && std::all_of(children.begin(), children.end(), [&](SharedRef r) { return r == first; })) return first;
        auto& table = level == 1 ? out_.nodes1 : out_.nodes2;
        auto& index = level == 1 ? nodes1_ : nodes2_;
        const auto [it, inserted] = index.emplace(children, std::uint32_t(table.size()));
        if (inserted) table.push_back({std::move(children)});
        return it->second;
    }

private:
    SharedTree& out_;
    std::unordered_map<std::uint64_t, std::uint32_t> tiles_;
    std::unordered_map<std::string, std::uint32_t> leaves_;
    std::map<std::vector<SharedRef>, std::uint32_t> nodes1_, nodes2_;
};

using Internal1 = openvdb::FloatTree::RootNodeType::ChildNodeType::ChildNodeType;
using Internal2 = openvdb::FloatTree::RootNodeType::ChildNodeType;

/// The shared map of one operation.
class SharedMap {
public:
    SharedMap(const SharedTree& in, const VoxelRule& rule, const openvdb::FloatGrid* other)
        : in_(in), rule_(rule), other_(other), conser_(out_) {
        out_.voxel_size = in.voxel_size;
        out_.background = in.background;
        out_.level_set = in.level_set;
        conser_.tile(in.tiles[0].value, false);
    }

    SharedTree run() {
        std::set<Coord3> positions;
        for (const SharedRootEntry& e : in_.root)
            for (int d = 0; d < 27; ++d)
                positions.insert({e.origin[0] + 4096 * (d / 9 - 1), e.origin[1] + 4096 * ((d / 3) % 3 - 1), e.origin[2] + 4096 * (d % 3 - 1)});
        if (other_) {  // where the other grid has anything, with its neighbours
            const auto& root = other_->tree().root();
            std::vector<openvdb::Coord> origins;
            for (auto it = root.cbeginChildOn(); it; ++it) origins.push_back(it->origin());
            for (auto it = root.cbeginValueAll(); it; ++it) origins.push_back(it.getCoord());
            for (const openvdb::Coord& c : origins)
                for (int d = 0; d < 27; ++d)
                    positions.insert({c.x() + 4096 * (d / 9 - 1), c.y() + 4096 * ((d / 3) % 3 - 1), c.z() + 4096 * (d % 3 - 1)});
        }
        // Leaf results first, in parallel: collect every leaf-level neighbourhood that needs
        // computing (distinct keys once), then compute them, then cons in walk order.
        for (const Coord3& p : positions) {
            Key27 key;
            for (int d = 0; d < 27; ++d) key[d] = in_.root_ref({p[0] + 4096 * (d / 9 - 1), p[1] + 4096 * ((d / 3) % 3 - 1), p[2] + 4096 * (d % 3 - 1)});
            const SharedRef r = walk(2, key, p, /*collect=*/true);
            (void)r;
        }
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pending_.size(), 4), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) pending_[i].result = compute_leaf(pending_[i].key, pending_[i].origin, pending_[i].context);
        });
        for (const Pending& p : pending_) {
            if (p.context == kNoContext) positional_.emplace(p.origin, p.result);
            else leaf_results_.emplace(with_context(p.key, p.context), p.result);
        }
        pending_.clear();
        for (const Coord3& p : positions) {
            Key27 key;
            for (int d = 0; d < 27; ++d) key[d] = in_.root_ref({p[0] + 4096 * (d / 9 - 1), p[1] + 4096 * ((d / 3) % 3 - 1), p[2] + 4096 * (d % 3 - 1)});
            const SharedRef r = walk(2, key, p, false);
            if (r != tile_ref(0)) out_.root.push_back({p, r});
        }
        return std::move(out_);
    }

    std::uint64_t distinct_leaf_computations() const { return computed_; }

private:
    using Key28 = std::array<SharedRef, 28>;
    static Key28 with_context(const Key27& k, std::uint32_t c) {
        Key28 out;
        std::copy(k.begin(), k.end(), out.begin());
        out[27] = c;
        return out;
    }

    /// What the other grid holds over the cube (with one leaf of margin): a tile id, or
    /// kNoContext when it varies there (then the result is positional).
    std::uint32_t context(const Coord3& o, int dim) {
        if (!rule_.uses_other || !other_) return 0;
        // Conservative: every node of the cube's size overlapping the cube and its margin of
        // 8 voxels is absent (a tile of the level above) and all those tiles are equal.
        if (!other_acc_) {  // the walk is serial
            other_acc_.emplace(other_->getConstAccessor());
            // Where the other grid holds anything but its background: leaves and other tiles.
            const float obg = other_->background();
            for (auto leaf = other_->tree().cbeginLeaf(); leaf; ++leaf) other_box_.expand(leaf->getNodeBoundingBox());
            for (auto it = other_->tree().cbeginValueAll(); it; ++it) {
                if (it.getVoxelCount() > 1 && (it.isValueOn() || std::memcmp(&*it, &obg, 4) != 0)) other_box_.expand(it.getBoundingBox());
            }
        }
        auto& tree = *other_acc_;
        const openvdb::Coord lo(o[0] - 8, o[1] - 8, o[2] - 8), hi(o[0] + dim + 7, o[1] + dim + 7, o[2] + dim + 7);
        if (!other_box_.hasOverlap(openvdb::CoordBBox(lo, hi))) {
            const float obg = other_->background();
            std::uint32_t bits;
            std::memcpy(&bits, &obg, 4);
            const auto [it, inserted] = contexts_.emplace(std::uint64_t(bits) << 1, std::uint32_t(contexts_.size()));
            if (inserted) context_values_.push_back(obg);
            return it->second;
        }
        auto floor_to = [dim](int v) { return int(std::floor(double(v) / dim)) * dim; };
        float v0 = 0;
        bool on0 = false, first = true;
        for (int x = floor_to(lo.x()); x <= hi.x(); x += dim)
            for (int y = floor_to(lo.y()); y <= hi.y(); y += dim)
                for (int z = floor_to(lo.z()); z <= hi.z(); z += dim) {
                    const openvdb::Coord c(x, y, z);
                    const bool node = dim == 8 ? tree.probeConstLeaf(c) != nullptr
                                      : dim == 128 ? tree.probeConstNode<Internal1>(c) != nullptr
                                                   : tree.probeConstNode<Internal2>(c) != nullptr;
                    if (node) return kNoContext;
                    const float v = tree.getValue(c);
                    const bool on = tree.isValueOn(c);
                    if (first) {
                        v0 = v;
                        on0 = on;
                        first = false;
                    } else if (std::memcmp(&v, &v0, 4) != 0 || on != on0) {
                        return kNoContext;
                    }
                }
        std::uint32_t bits;
        std::memcpy(&bits, &v0, 4);
        const std::uint64_t key = (std::uint64_t(bits) << 1) | (on0 ? 1 : 0);
        const auto [it, inserted] = contexts_.emplace(key, std::uint32_t(contexts_.size()));
        if (inserted) context_values_.push_back(v0);
        return it->second;
    }

    SharedRef child_ref(int level, SharedRef parent, int index) const {
        if (is_tile(parent)) return parent;
        return level == 2 ? in_.nodes2[parent].children[index] : in_.nodes1[parent].children[index];
    }

    bool all_same_tile(const Key27& key) const {
        return is_tile(key[0]) && std::all_of(key.begin(), key.end(), [&](SharedRef r) { return r == key[0]; });
    }

    /// The output ref of the level-@a level cube at @a origin whose neighbourhood is @a key.
    SharedRef walk(int level, const Key27& key, const Coord3& origin, bool collect, std::uint32_t parent_ctx = kNoContext) {
        const int dim = kSharedDim[level];
        // A uniform context of the parent (its cube and margin) holds for the child as well.
        const std::uint32_t ctx = parent_ctx != kNoContext ? parent_ctx : context(origin, dim);
        if (all_same_tile(key) && ctx != kNoContext) {
            const SharedTile& t = in_.tiles[key[0] & ~kSharedTile];
            const float w = rule_.uses_other && other_ ? context_values_[ctx] : 0.0f;
            if (collect) return 0;
            if (is_background(t.value, t.active, in_.background) && !rule_.uses_other) return tile_ref(0);
            const float v = rule_.tile(t.value, w);
            const bool active = (v == t.value) ? t.active : (v > -in_.background && v < in_.background);
            return conser_.tile(v, active);
        }
        if (level == 0) {
            if (collect) {
                if (ctx == kNoContext) pending_.push_back({key, origin, ctx, {}});
                else if (seen_.insert(with_context(key, ctx)).second) pending_.push_back({key, origin, ctx, {}});
                return 0;
            }
            const SharedLeaf& leaf = ctx == kNoContext ? positional_.at(origin) : leaf_results_.at(with_context(key, ctx));
            return conser_.leaf(leaf);
        }
        auto& memo = level == 1 ? memo1_ : memo2_;
        if (!collect && ctx != kNoContext) {
            const auto it = memo.find(with_context(key, ctx));
            if (it != memo.end()) return it->second;
        }
        if (collect && ctx != kNoContext && !collected_[level].insert(with_context(key, ctx)).second) return 0;
        const int n = kSharedChildren[level], cdim = kSharedDim[level - 1];
        std::vector<SharedRef> children(std::size_t(n) * n * n);
        for (int x = 0; x < n; ++x)
            for (int y = 0; y < n; ++y)
                for (int z = 0; z < n; ++z) {
                    Key27 ck;
                    for (int d = 0; d < 27; ++d) {
                        const int q[3] = {x + d / 9 - 1, y + (d / 3) % 3 - 1, z + d % 3 - 1};
                        int p = 0, local = 0;
                        for (int a = 0; a < 3; ++a) {
                            const int pa = q[a] < 0 ? 0 : q[a] >= n ? 2 : 1;
                            const int la = q[a] < 0 ? q[a] + n : q[a] >= n ? q[a] - n : q[a];
                            p = p * 3 + pa;
                            local = local * n + la;
                        }
                        ck[d] = child_ref(level, key[p], local);
                    }
                    children[std::size_t((x * n + y) * n + z)] =
                        walk(level - 1, ck, {origin[0] + x * cdim, origin[1] + y * cdim, origin[2] + z * cdim}, collect, ctx);
                }
        if (collect) return 0;
        const SharedRef r = conser_.node(level, std::move(children));
        if (ctx != kNoContext) memo.emplace(with_context(key, ctx), r);
        return r;
    }

    SharedLeaf compute_leaf(const Key27& key, const Coord3& origin, std::uint32_t ctx) {
        ++computed_;
        // The 24^3 samples around the leaf.
        std::vector<float> samples(kS * kS * kS);
        for (int x = 0; x < kS; ++x)
            for (int y = 0; y < kS; ++y)
                for (int z = 0; z < kS; ++z) {
                    const int d = (x / 8) * 9 + (y / 8) * 3 + (z / 8);
                    const SharedRef r = key[d];
                    samples[std::size_t((x * kS + y) * kS + z)] =
                        is_tile(r) ? in_.tiles[r & ~kSharedTile].value : in_.leaves[r].values[((x & 7) * 8 + (y & 7)) * 8 + (z & 7)];
                }
        std::optional<openvdb::FloatGrid::ConstAccessor> acc;
        if (rule_.uses_other && other_ && ctx == kNoContext) acc.emplace(other_->getConstAccessor());
        const float ctx_value = rule_.uses_other && other_ && ctx != kNoContext ? context_values_[ctx] : 0.0f;
        SharedLeaf out;
        for (int x = 0; x < 8; ++x)
            for (int y = 0; y < 8; ++y)
                for (int z = 0; z < 8; ++z) {
                    const std::function<float(int, int, int)> other = [&](int dx, int dy, int dz) {
                        if (!acc) return ctx_value;
                        return acc->getValue(openvdb::Coord(origin[0] + x + dx, origin[1] + y + dy, origin[2] + z + dz));
                    };
                    store(out, (x * 8 + y) * 8 + z, rule_.apply(samples.data(), sample_delta(x + 8, y + 8, z + 8), other), in_.background);
                }
        return out;
    }

    struct Pending {
        Key27 key;
        Coord3 origin;
        std::uint32_t context;
        SharedLeaf result;
    };

    const SharedTree& in_;
    const VoxelRule& rule_;
    const openvdb::FloatGrid* other_;
    SharedTree out_;
    Conser conser_;
    std::vector<Pending> pending_;
    std::set<Key28> seen_;
    std::array<std::set<Key28>, 3> collected_;
    std::map<Key28, SharedLeaf> leaf_results_;
    std::map<Coord3, SharedLeaf> positional_;
    std::map<Key28, SharedRef> memo1_, memo2_;
    std::unordered_map<std::uint64_t, std::uint32_t> contexts_;
    std::optional<openvdb::FloatGrid::ConstAccessor> other_acc_;
    openvdb::CoordBBox other_box_;
    std::vector<float> context_values_;
    std::uint64_t computed_ = 0;
};

void check_distance(const char* flag, double value) {
    if (!(value >= 0) || !std::isfinite(value)) throw UsageError(std::string(flag) + ": expected a non-negative distance");
}

/// Plain reference: the same rule voxel by voxel on the expanded grid, over every leaf and the
/// leaves next to them.
openvdb::FloatGrid::Ptr plain_map(const openvdb::FloatGrid& in, const VoxelRule& rule, const openvdb::FloatGrid* other) {
    auto out = in.deepCopy();
    std::set<openvdb::Coord> positions;
    for (auto leaf = in.tree().cbeginLeaf(); leaf; ++leaf)
        for (int d = 0; d < 27; ++d) positions.insert(leaf->origin().offsetBy(8 * (d / 9 - 1), 8 * ((d / 3) % 3 - 1), 8 * (d % 3 - 1)));
    // Tiles other than the background change next to anything different: the leaf cells of
    // their shell (one leaf deep on both sides of the boundary).
    const float background = in.background();
    auto add_shells = [&](const openvdb::FloatGrid& g) {
        auto tile = g.tree().cbeginValueAll();
        tile.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);
        for (; tile; ++tile) {
            if (!tile.isValueOn() && std::memcmp(&*tile, &background, 4) == 0) continue;
            const openvdb::CoordBBox box = tile.getBoundingBox();
            const openvdb::Coord lo = box.min().offsetBy(-8), hi = box.max().offsetBy(8);
            for (int x = lo.x(); x <= hi.x(); x += 8)
                for (int y = lo.y(); y <= hi.y(); y += 8)
                    for (int z = lo.z(); z <= hi.z(); z += 8) {
                        const bool interior = x >= box.min().x() + 8 && x + 7 <= box.max().x() - 8 && y >= box.min().y() + 8 &&
                                              y + 7 <= box.max().y() - 8 && z >= box.min().z() + 8 && z + 7 <= box.max().z() - 8;
                        if (!interior) positions.insert(openvdb::Coord(x, y, z));
                    }
        }
    };
    add_shells(in);
    if (other) {
        add_shells(*other);
        for (auto leaf = other->tree().cbeginLeaf(); leaf; ++leaf)
            for (int d = 0; d < 27; ++d) positions.insert(leaf->origin().offsetBy(8 * (d / 9 - 1), 8 * ((d / 3) % 3 - 1), 8 * (d % 3 - 1)));
    }
    std::vector<openvdb::Coord> list(positions.begin(), positions.end());
    std::vector<std::unique_ptr<openvdb::FloatTree::LeafNodeType>> made(list.size());
    const float bg = in.background();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, list.size(), 8), [&](const auto& range) {
        auto acc = in.getConstAccessor();
        std::vector<float> samples(kS * kS * kS);
        std::optional<openvdb::FloatGrid::ConstAccessor> oacc;
        if (other) oacc.emplace(other->getConstAccessor());
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const openvdb::Coord o = list[i];
            for (int x = 0; x < kS; ++x)
                for (int y = 0; y < kS; ++y)
                    for (int z = 0; z < kS; ++z) samples[std::size_t(sample_delta(x, y, z))] = acc.getValue(o.offsetBy(x - 8, y - 8, z - 8));
            SharedLeaf leaf;
            for (int x = 0; x < 8; ++x)
                for (int y = 0; y < 8; ++y)
                    for (int z = 0; z < 8; ++z) {
                        const std::function<float(int, int, int)> oth = [&](int dx, int dy, int dz) {
                            return oacc ? oacc->getValue(o.offsetBy(x + dx, y + dy, z + dz)) : 0.0f;
                        };
                        store(leaf, (x * 8 + y) * 8 + z, rule.apply(samples.data(), sample_delta(x + 8, y + 8, z + 8), oth), bg);
                    }
            auto node = std::make_unique<openvdb::FloatTree::LeafNodeType>(o, bg);
            for (int v = 0; v < 512; ++v) {
                node->setValueOnly(openvdb::Index(v), leaf.values[v]);
                node->setActiveState(openvdb::Index(v), leaf.is_active(v));
            }
            made[i] = std::move(node);
        }
    });
    // Tiles away from the leaves: the tile rule (other grid: its value at the tile).
    auto oacc = other ? std::optional<openvdb::FloatGrid::ConstAccessor>(other->getConstAccessor()) : std::nullopt;
    for (auto it = out->tree().beginValueAll(); it; ++it) {
        if (it.getVoxelCount() == 1) continue;
        const float w = oacc ? oacc->getValue(it.getCoord()) : 0.0f;
        const float v = rule.tile(*it, w);
        if (std::memcmp(&v, &*it, 4) != 0) {
            it.setValue(v);
            it.setActiveState(v > -bg && v < bg);
        }
    }
    for (auto& node : made) out->tree().addLeaf(node.release());
    return out;
}

}  // namespace

SharedTree shared_deposit(const SharedTree& tree, double distance) {
    check_distance("--deposit", distance);
    SharedTree current = tree;
    // Passes of at most 7 voxels: a leaf's result reads at most 8 voxels around it.
    double left = distance;
    do {
        const double step = std::min(left, 7.0 * tree.voxel_size);
        const VoxelRule rule = deposit_rule(step, tree.voxel_size, tree.background);
        current = SharedMap(current, rule, nullptr).run();
        left -= step;
    } while (left > 1e-12);
    return current;
}

SharedTree shared_etch(const SharedTree& tree, int axis, int sign, double depth, const openvdb::FloatGrid* stop) {
    if (axis < 0 || axis > 2 || (sign != 1 && sign != -1)) throw UsageError("--etch: expected an axis x, y or z");
    check_distance("--etch", depth);
    int steps = int(std::llround(depth / tree.voxel_size));
    SharedTree current = tree;
    do {
        const int pass = std::min(steps, 8);
        const VoxelRule rule = etch_rule(axis, sign, pass, stop != nullptr);
        current = SharedMap(current, rule, stop).run();
        steps -= pass;
    } while (steps > 0);
    return current;
}

SharedTree shared_csg(const SharedTree& tree, const openvdb::FloatGrid& other, CsgOp op) {
    const VoxelRule rule = csg_rule(op);
    return SharedMap(tree, rule, &other).run();
}

openvdb::FloatGrid::Ptr plain_deposit(const openvdb::FloatGrid& grid, double distance) {
    openvdb::FloatGrid::Ptr current = grid.deepCopy();
    const double h = grid.voxelSize()[0];
    double left = distance;
    do {
        const double step = std::min(left, 7.0 * h);
        current = plain_map(*current, deposit_rule(step, h, grid.background()), nullptr);
        left -= step;
    } while (left > 1e-12);
    return current;
}

openvdb::FloatGrid::Ptr plain_etch(const openvdb::FloatGrid& grid, int axis, int sign, double depth, const openvdb::FloatGrid* stop) {
    int steps = int(std::llround(depth / grid.voxelSize()[0]));
    openvdb::FloatGrid::Ptr current = grid.deepCopy();
    do {
        const int pass = std::min(steps, 8);
        current = plain_map(*current, etch_rule(axis, sign, pass, stop != nullptr), stop);
        steps -= pass;
    } while (steps > 0);
    return current;
}

openvdb::FloatGrid::Ptr plain_csg(const openvdb::FloatGrid& grid, const openvdb::FloatGrid& other, CsgOp op) {
    return plain_map(grid, csg_rule(op), &other);
}

}  // namespace vdbmesh
