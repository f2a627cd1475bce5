// The topology test of a merge from leaf children, by their 27 corner signs (dc_topology.h).
// A face of the children's lattice has 3 x 3 signs, so what the test needs of a face comes
// from a table of the 512 cases.

#include "mesh/dc_topology.h"

#include <cstddef>
#include <numeric>

namespace vdbmesh::detail {

namespace {

/// The bit of the corner at @a a along @a axis, @a u along (axis + 1) % 3 and @a w along (axis + 2) % 3.
int corner_bit(int axis, int a, int u, int w) {
    std::array<int, 3> p{};
    p[axis] = a;
    p[(axis + 1) % 3] = u;
    p[(axis + 2) % 3] = w;
    return p[0] * 9 + p[1] * 3 + p[2];
}

/// The child at @a a along @a axis, @a u and @a w across it (each 0 or 1).
int child_index(int axis, int a, int u, int w) {
    std::array<int, 3> p{};
    p[axis] = a;
    p[(axis + 1) % 3] = u;
    p[(axis + 2) % 3] = w;
    return p[0] | p[1] << 1 | p[2] << 2;
}

/// The surface's trace on a face of the children's lattice, from its 3 x 3 signs.
struct FaceTrace {
    std::uint8_t chains = 0;  ///< bit q (quarter u + 2 w): a chain crosses that quarter
    bool ambiguous = false;   ///< a quarter whose four edges all change sign
    /// As a face of the cell: each of its edges changes sign at most once, and the trace is
    /// one path or nothing (no loop, no ambiguous quarter).
    bool simple_boundary = false;
};

FaceTrace trace_of(unsigned code) {
    auto sign = [&](int u, int w) { return (code >> (u + 3 * w)) & 1; };
    FaceTrace trace;
    for (int q = 0; q < 4; ++q) {
        const int u = q & 1, w = q >> 1;
        const int changes = (sign(u, w) != sign(u + 1, w)) + (sign(u, w + 1) != sign(u + 1, w + 1)) +
                            (sign(u, w) != sign(u, w + 1)) + (sign(u + 1, w) != sign(u + 1, w + 1));
        trace.ambiguous |= changes == 4;
        if (changes == 2) trace.chains |= std::uint8_t(1 << q);
    }
    // Perimeter: the half edges along u at w = 0 and 2, along w at u = 0 and 2.
    int boundary_crossings = 0;
    bool edges_simple = true;
    for (int side : {0, 2}) {
        const int along_u = (sign(0, side) != sign(1, side)) + (sign(1, side) != sign(2, side));
        const int along_w = (sign(side, 0) != sign(side, 1)) + (sign(side, 1) != sign(side, 2));
        boundary_crossings += along_u + along_w;
        edges_simple &= along_u <= 1 && along_w <= 1;
    }
    // Inner half edges join the two quarters beside them; a component with no perimeter
    // crossing is a loop.
    std::array<int, 4> parent = {0, 1, 2, 3};
    auto find = [&](int i) {
        while (parent[i] != i) i = parent[i];
        return i;
    };
    if (sign(1, 1) != sign(0, 1)) parent[find(2)] = find(0);
    if (sign(1, 1) != sign(2, 1)) parent[find(3)] = find(1);
    if (sign(1, 1) != sign(1, 0)) parent[find(1)] = find(0);
    if (sign(1, 1) != sign(1, 2)) parent[find(3)] = find(2);
    int components = 0;
    for (int q = 0; q < 4; ++q) components += (trace.chains >> q & 1) && find(q) == q;
    trace.simple_boundary = edges_simple && !trace.ambiguous && boundary_crossings <= 2 && components * 2 == boundary_crossings;
    return trace;
}

const std::array<FaceTrace, 512>& face_traces() {
    static const std::array<FaceTrace, 512> traces = [] {
        std::array<FaceTrace, 512> result;
        for (unsigned code = 0; code < 512; ++code) result[code] = trace_of(code);
        return result;
    }();
    return traces;
}

/// The 9-bit code (bit u + 3 w) of the face normal to @a axis at plane @a a.
unsigned face_code(ChildCornerSigns signs, int axis, int a) {
    static const auto bits = [] {
        std::array<std::array<std::array<std::uint8_t, 9>, 3>, 3> result;
        for (int n = 0; n < 3; ++n) {
            for (int p = 0; p < 3; ++p) {
                for (int k = 0; k < 9; ++k) result[n][p][k] = std::uint8_t(corner_bit(n, p, k % 3, k / 3));
            }
        }
        return result;
    }();
    unsigned code = 0;
    for (int k = 0; k < 9; ++k) code |= ((signs >> bits[axis][a][k]) & 1u) << k;
    return code;
}

bool one_disk_by_signs(ChildCornerSigns signs, const std::array<bool, 8>& surface) {
    const auto& traces = face_traces();
    for (int axis = 0; axis < 3; ++axis) {
        if (!traces[face_code(signs, axis, 0)].simple_boundary || !traces[face_code(signs, axis, 2)].simple_boundary) return false;
    }
    std::array<int, 8> parent;
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int i) {
        while (parent[i] != i) i = parent[i];
        return i;
    };
    int chi = 0;
    for (int c = 0; c < 8; ++c) chi += surface[c];
    const bool centre = (signs >> 13) & 1;
    for (int axis = 0; axis < 3; ++axis) {
        const FaceTrace& inner = traces[face_code(signs, axis, 1)];
        if (inner.ambiguous) return false;
        for (int q = 0; q < 4; ++q) {
            if (!(inner.chains >> q & 1)) continue;
            --chi;
            parent[find(child_index(axis, 0, q & 1, q >> 1))] = find(child_index(axis, 1, q & 1, q >> 1));
        }
        // The inner half edges along this axis, from the centre to either side: the four
        // children round each share its crossing.
        for (int a : {0, 1}) {
            if (centre == bool((signs >> corner_bit(axis, 2 * a, 1, 1)) & 1)) continue;
            ++chi;
            for (int q = 1; q < 4; ++q) parent[find(child_index(axis, a, q & 1, q >> 1))] = find(child_index(axis, a, 0, 0));
        }
    }
    int components = 0;
    for (int c = 0; c < 8; ++c) components += surface[c] && find(c) == c;
    return components == 1 && chi == 1;
}

}  // namespace

bool union_is_one_disk(ChildCornerSigns signs, const std::array<bool, 8>& surface) {
    // The answer depends on 35 bits only, and neighbouring cells of a smooth surface repeat a
    // few sign patterns: a small per-thread table of recent answers saves most of the work
    // (about 4% of DC's time on the bunny went to this test).
    static constexpr std::size_t kSlots = 4096;
    struct Slot {
        std::uint64_t key_plus_one = 0;  // 0: empty
        bool answer = false;
    };
    thread_local std::array<Slot, kSlots> recent;
    std::uint64_t key = signs;
    for (int c = 0; c < 8; ++c) key |= std::uint64_t(surface[c]) << (27 + c);
    static_assert(kSlots == std::size_t(1) << 12, "the hash keeps 12 bits");
    Slot& slot = recent[(key * 0x9e3779b97f4a7c15ull) >> (64 - 12)];
    if (slot.key_plus_one != key + 1) slot = {key + 1, one_disk_by_signs(signs, surface)};
    return slot.answer;
}

}  // namespace vdbmesh::detail
