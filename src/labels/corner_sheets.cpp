// The sheets through a voxel corner and the manifold check per label (corner_sheets.h).

#include "labels/corner_sheets.h"

#include <algorithm>
#include <utility>

namespace vdbmesh::labels_detail {
namespace {

/// Union-find over the 12 faces, small enough to copy.
struct FaceSets {
    std::array<std::int8_t, 12> parent;
    FaceSets() {
        for (int f = 0; f < 12; ++f) parent[f] = std::int8_t(f);
    }
    int find(int f) {
        while (parent[f] != f) f = parent[f] = parent[parent[f]];
        return f;
    }
    void join(int a, int b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::int8_t(std::min(a, b));
    }
};

/// The face between two octants that differ in one bit.
int face_between(int a, int b) {
    const int low = a & b, axis = __builtin_ctz(unsigned(a ^ b)), u = (axis + 1) % 3, v = (axis + 2) % 3;
    return 4 * axis + ((low >> u) & 1) + 2 * ((low >> v) & 1);
}

/// Two walls joined at an edge by a curve.
struct Pair {
    int a = -1, b = -1;
};

/// What happens at one edge from the corner.
struct EdgeJoins {
    int axis = 0, side = 0;
    std::array<int, 4> octant;     ///< q0..q3 round the edge, in cyclic order
    std::array<int, 4> face;       ///< face i between q_i and q_{i+1}
    std::array<Pair, 4> run_pair;  ///< per octant starting a run: the walls bounding its run
    int bridged = -1;              ///< -1, or 0 / 1: the diagonal q0 q2 / q1 q3 is bridged
};

/// Whether the diagonal voxels q_i, q_{i+2} (same label) are joined through the layer beyond
/// both ends of the edge: in the block's other layer and in the layer beyond the far end.
bool wraps_round(const CornerNeighbourhood& n, const EdgeJoins& e, int i) {
    const int flip = 1 << e.axis;
    const std::uint16_t label = n.block[e.octant[i]];
    const auto near = [&](int k) { return n.block[e.octant[k % 4] ^ flip] == label; };
    const auto far = [&](int k) { return n.far[2 * e.axis + e.side][far_index(e.axis, e.octant[k % 4])] == label; };
    return near(i) && near(i + 2) && (near(i + 1) || near(i + 3)) && far(i) && far(i + 2) && (far(i + 1) || far(i + 3));
}

EdgeJoins edge_joins(const CornerNeighbourhood& n, int axis, int side) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3, base = side << axis;
    EdgeJoins e;
    e.axis = axis, e.side = side;
    e.octant = {base, base | (1 << u), base | (1 << u) | (1 << v), base | (1 << v)};
    for (int i = 0; i < 4; ++i) e.face[i] = face_between(e.octant[i], e.octant[(i + 1) % 4]);
    std::array<std::uint16_t, 4> l;
    for (int i = 0; i < 4; ++i) l[i] = n.block[e.octant[i]];
    const bool diag02 = l[0] == l[2] && l[1] != l[0] && l[3] != l[0];
    const bool diag13 = l[1] == l[3] && l[0] != l[1] && l[2] != l[1];
    if (diag02 && diag13) {
        // At most one of the two can wrap round (they would have to share a voxel of a layer).
        e.bridged = wraps_round(n, e, 0) ? 0 : wraps_round(n, e, 1) ? 1 : l[0] < l[1] ? 0 : 1;
    } else if (diag02) {
        e.bridged = 0;
    } else if (diag13) {
        e.bridged = 1;
    }
    if (e.bridged >= 0) {  // the two other octants are runs of their own
        const int o = 1 - e.bridged;
        e.run_pair[o] = {e.face[(o + 3) % 4], e.face[o]};
        e.run_pair[o + 2] = {e.face[(o + 1) % 4], e.face[o + 2]};
        return e;
    }
    for (int i = 0; i < 4; ++i) {
        if (l[(i + 3) % 4] == l[i]) continue;  // not the start of a run
        int j = i;
        while (l[(j + 1) % 4] == l[i]) j = (j + 1) % 4;
        e.run_pair[i] = {e.face[(i + 3) % 4], e.face[j]};
    }
    return e;
}

/// The pairs of @a label's curves at edge @a e (at most two).
std::array<Pair, 2> label_pairs(const EdgeJoins& e, const CornerLabels& labels, std::uint16_t label) {
    std::array<Pair, 2> pairs;
    int n = 0;
    const bool bridged = e.bridged >= 0 && labels[e.octant[e.bridged]] == label;
    for (int i = 0; i < 4; ++i) {
        if (e.run_pair[i].a < 0) continue;
        if (bridged || labels[e.octant[i]] == label) pairs[n++] = e.run_pair[i];
    }
    return pairs;
}

bool is_wall(const CornerLabels& labels, int f) { return labels[face_low_octant(f)] != labels[face_high_octant(f)]; }

bool uniform(const CornerLabels& labels) {
    return std::all_of(labels.begin(), labels.end(), [&](std::uint16_t l) { return l == labels[0]; });
}

std::array<EdgeJoins, 6> all_edges(const CornerNeighbourhood& n) {
    std::array<EdgeJoins, 6> edges;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) edges[2 * axis + side] = edge_joins(n, axis, side);
    return edges;
}

}  // namespace

CornerSheets corner_sheets(const CornerNeighbourhood& n) {
    CornerSheets result;
    result.sheet.fill(-1);
    if (uniform(n.block)) return result;
    FaceSets sheets;
    for (const EdgeJoins& e : all_edges(n))
        for (const Pair& p : e.run_pair)
            if (p.a >= 0) sheets.join(p.a, p.b);
    std::array<int, 12> root{};
    for (int f = 0; f < 12; ++f) {
        if (!is_wall(n.block, f)) continue;
        root[f] = sheets.find(f);
        if (root[f] == f) result.sheet[f] = std::int8_t(result.count++);
    }
    for (int f = 0; f < 12; ++f)
        if (result.sheet[f] < 0 && is_wall(n.block, f)) result.sheet[f] = result.sheet[root[f]];
    return result;
}

std::uint16_t corner_conflict(const CornerNeighbourhood& n, const CornerSheets& sheets,
                              const std::function<bool(std::uint16_t)>& checked,
                              const std::function<CornerSheets(int)>& far_sheets) {
    if (uniform(n.block)) return 0;
    const std::array<EdgeJoins, 6> edges = all_edges(n);
    for (int o = 0; o < 8; ++o) {
        const std::uint16_t label = n.block[o];
        if (!checked(label) || std::find(n.block.begin(), n.block.begin() + o, label) != n.block.begin() + o) continue;
        FaceSets curves;
        for (int k = 0; k < 6; ++k) {
            const EdgeJoins& e = edges[k];
            const std::array<Pair, 2> pairs = label_pairs(e, n.block, label);
            for (const Pair& p : pairs)
                if (p.a >= 0) curves.join(p.a, p.b);
            if (pairs[1].a < 0 || sheets.sheet[pairs[0].a] != sheets.sheet[pairs[1].a]) continue;
            // Both pairs on one sheet here: the edge to the far corner carries four of the
            // label's walls unless they part there.
            const CornerSheets far = far_sheets(k);
            const int flip = 1 << e.axis;
            const auto far_face = [&](int face) {
                return face_between(face_low_octant(face) ^ flip, face_high_octant(face) ^ flip);
            };
            if (far.sheet[far_face(pairs[0].a)] == far.sheet[far_face(pairs[1].a)]) return label;
        }
        std::array<int, 12> curve_of_sheet;
        curve_of_sheet.fill(-1);
        for (int f = 0; f < 12; ++f) {
            if (!is_wall(n.block, f) || (n.block[face_low_octant(f)] != label && n.block[face_high_octant(f)] != label)) continue;
            int& curve = curve_of_sheet[std::size_t(sheets.sheet[f])];
            const int c = curves.find(f);
            if (curve < 0) curve = c;
            else if (curve != c) return label;
        }
    }
    return 0;
}

}  // namespace vdbmesh::labels_detail
