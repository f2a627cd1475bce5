// The nodes of a splat tree a camera needs (QSplat's traversal by projected size, with
// frustum and normal-cone culling), largest first under a budget; over a plain tree or a
// shared one (its placed subtrees entered as the traversal reaches them).

#include <algorithm>
#include <cmath>
#include <queue>
#include <utility>

#include "vdbmesh/shared_splats.h"
#include "vdbmesh/splats.h"

namespace vdbmesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

using Vec3 = std::array<double, 3>;

Vec3 vec(const std::array<float, 3>& a) { return {a[0], a[1], a[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double length(const Vec3& a) { return std::sqrt(dot(a, a)); }

/// The six planes of the view frustum (Gribb and Hartmann), normalised, pointing inwards:
/// a point p is inside when dot(n, p) + d >= 0 for all.
std::array<std::array<double, 4>, 6> frustum_planes(const std::array<double, 16>& m) {
    const auto row = [&](int r) { return std::array<double, 4>{m[r], m[4 + r], m[8 + r], m[12 + r]}; };
    const auto w = row(3);
    std::array<std::array<double, 4>, 6> planes{};
    for (int axis = 0; axis < 3; ++axis) {
        const auto r = row(axis);
        for (int i = 0; i < 4; ++i) {
            planes[2 * axis][i] = w[i] + r[i];
            planes[2 * axis + 1][i] = w[i] - r[i];
        }
    }
    for (auto& p : planes) {
        const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        if (n > 0)
            for (double& x : p) x /= n;
    }
    return planes;
}

/// A node of a tree as the traversal addresses it: an index (a plain tree) or an index with
/// the placed subtree it lies in (a shared tree, shared_splats.h).
using Handle = std::uint64_t;

/// QSplat's traversal over @a Tree, which gives node(handle) (in world space) and
/// child(handle, node, c), the handle of its c-th child.
template <class Tree>
class Traversal {
public:
    Traversal(const Tree& tree, const SplatView& view) : tree_(tree), view_(view), planes_(frustum_planes(view.view_projection)) {}

    /// The selection's figures, its nodes' handles in @a shown.
    SplatSelection run(std::vector<Handle>& shown_nodes) {
        SplatSelection selection;
        if (tree_.empty()) return selection;
        if (visible(tree_.node(0))) push(0);
        std::size_t shown = 0;  // nodes kept so far; the queue's nodes are shown too if the traversal stops
        while (!queue_.empty()) {
            const auto [size, handle] = queue_.top();
            queue_.pop();
            const SplatNode node = tree_.node(handle);
            const bool wants_children = node.child_count != 0 && size > view_.pixel_size;
            const std::size_t visible_children = wants_children ? count_visible(handle, node) : 0;
            if (wants_children && visible_children == 0) continue;  // its sphere peeks in, its surface does not
            const bool refine = wants_children && shown + queue_.size() + visible_children <= view_.budget;
            if (!refine) {
                if (wants_children) selection.complete = false;
                shown_nodes.push_back(handle);
                selection.finest_level = std::min(selection.finest_level, node.level);
                if (node.child_count != 0) selection.cut_level = std::max(selection.cut_level, int(node.level));
                ++shown;
                continue;
            }
            for (std::uint32_t c = 0; c < node.child_count; ++c) {
                const Handle child = tree_.child(handle, node, c);
                if (visible(tree_.node(child))) push(child);
            }
        }
        std::sort(shown_nodes.begin(), shown_nodes.end());
        return selection;
    }

private:
    bool in_frustum(const SplatNode& node) const {
        for (const auto& p : planes_)
            if (p[0] * node.centre[0] + p[1] * node.centre[1] + p[2] * node.centre[2] + p[3] < -node.radius) return false;
        return true;
    }

    /// Whether some normal of the cone may face some point of the node's sphere towards the eye.
    bool may_face_eye(const SplatNode& node) const {
        const Vec3 to_eye{view_.eye[0] - node.centre[0], view_.eye[1] - node.centre[1], view_.eye[2] - node.centre[2]};
        const double distance = length(to_eye);
        if (distance <= node.radius || node.cone >= kPi / 2) return true;
        const double angle = std::acos(std::clamp(dot(vec(node.normal), to_eye) / distance, -1.0, 1.0));
        return angle <= kPi / 2 + node.cone + std::asin(node.radius / distance);
    }

    bool visible(const SplatNode& node) const { return in_frustum(node) && may_face_eye(node); }

    std::size_t count_visible(Handle handle, const SplatNode& node) const {
        std::size_t count = 0;
        for (std::uint32_t c = 0; c < node.child_count; ++c) count += visible(tree_.node(tree_.child(handle, node, c)));
        return count;
    }

    void push(Handle handle) { queue_.emplace(projected_splat_size(tree_.node(handle), view_), handle); }

    const Tree& tree_;
    const SplatView& view_;
    const std::array<std::array<double, 4>, 6> planes_;
    /// Largest first; equal sizes by the larger handle (deterministic either way).
    std::priority_queue<std::pair<double, Handle>> queue_;
};

/// A plain tree: a handle is a node's index.
struct PlainNodes {
    const SplatTree& tree;
    bool empty() const { return tree.nodes.empty(); }
    const SplatNode& node(Handle h) const { return tree.nodes[h]; }
    Handle child(Handle, const SplatNode& node, std::uint32_t c) const { return node.first_child + c; }
};

/// A shared tree: a handle's high 32 bits are 0 for the top's nodes, else 1 + the placed
/// subtree's index, its low 32 bits the node's index there. A placed node of the top is its
/// subtree's root (the same node), so its children are the subtree's.
struct SharedNodes {
    const SharedSplatTree& tree;
    bool empty() const { return tree.top.nodes.empty(); }

    SplatNode node(Handle h) const {
        const auto place = std::uint32_t(h >> 32), index = std::uint32_t(h);
        if (place == 0 && index < tree.first_placed) return tree.top.nodes[index];
        const std::uint32_t placed = place == 0 ? std::uint32_t(index - tree.first_placed) : place - 1;
        const SharedSplatTree::Placed& p = tree.placed[placed];
        SplatNode n = tree.subtrees[p.subtree][place == 0 ? 0 : index];
        for (int a = 0; a < 3; ++a) n.centre[a] = float(n.centre[a] + p.offset[a]);
        return n;
    }

    Handle child(Handle h, const SplatNode& node, std::uint32_t c) const {
        const auto place = std::uint32_t(h >> 32), index = std::uint32_t(h);
        if (place == 0 && index < tree.first_placed) return node.first_child + c;
        const Handle subtree = place == 0 ? Handle(index - tree.first_placed) + 1 : place;
        return (subtree << 32) | (node.first_child + c);
    }
};

}  // namespace

double projected_splat_size(const SplatNode& node, const SplatView& view) {
    const auto& m = view.view_projection;
    const double w = m[3] * node.centre[0] + m[7] * node.centre[1] + m[11] * node.centre[2] + m[15];
    if (w <= node.radius) return INFINITY;
    return 2 * node.radius * view.focal_pixels / w;
}

SplatSelection select_splats(const SplatTree& tree, const SplatView& view) {
    std::vector<Handle> shown;
    SplatSelection selection = Traversal<PlainNodes>(PlainNodes{tree}, view).run(shown);
    selection.nodes.assign(shown.begin(), shown.end());
    return selection;
}

SharedSplatSelection select_splats(const SharedSplatTree& tree, const SplatView& view) {
    const SharedNodes nodes{tree};
    std::vector<Handle> shown;
    SharedSplatSelection selection{Traversal<SharedNodes>(nodes, view).run(shown), {}};
    selection.nodes.reserve(shown.size());
    for (Handle h : shown) selection.nodes.push_back(nodes.node(h));
    return selection;
}

}  // namespace vdbmesh
