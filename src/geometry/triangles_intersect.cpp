// triangles_intersect(): which exact test of triangle_intersection.cpp applies to a pair of
// triangles, by the corners they share; for prepared triangles, with the quick proof of
// separating_plane.h for that case tried first.
#include "vdbmesh/separating_plane.h"
#include "geometry/triangle_intersection.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh::detail {
namespace {

using Ids = std::array<std::uint32_t, 3>;

/// The triangle's corners starting from corner @a first (a rotation: same orientation).
Triangle3 rotated(const Triangle3& t, int first) { return {t[first], t[(first + 1) % 3], t[(first + 2) % 3]}; }

bool shares(std::uint32_t id, const Ids& ids) { return id == ids[0] || id == ids[1] || id == ids[2]; }

/// No quick proof: the exact test alone.
struct Unproven {
    bool apart() const { return false; }
    bool apart_beyond_corner(int, int) const { return false; }
    bool apart_beyond_edge(const Point3&, const Point3&, const Point3&, const Point3&) const { return false; }
};

/// The proofs of separating_plane.h for each way the triangles share corners.
struct Proven {
    const PreparedTriangle &t, &u;
    bool apart() const { return certainly_apart(t, u) || certainly_apart_by_plane(t, u); }
    /// Sharing t's corner @a k and u's corner @a j (the planes first: the cheaper proof, and
    /// enough where the surface bends).
    bool apart_beyond_corner(int k, int j) const {
        return certainly_apart_of_plane(t, k, u, j) || certainly_meet_only_at(t.corners, k, u.corners[(j + 1) % 3], u.corners[(j + 2) % 3]);
    }
    bool apart_beyond_edge(const Point3& s0, const Point3& s1, const Point3& p, const Point3& q) const {
        return certainly_meet_only_on_edge(s0, s1, p, q);
    }
};

/// The exact tests of triangle_intersection.cpp.
struct Exact {
    bool meet(const Triangle3& t, const Triangle3& u) const { return triangles_meet(t, u); }
    bool meet_beyond_corner(const Triangle3& t, const Triangle3& u) const { return triangles_meet_beyond_corner(t, u); }
    bool meet_beyond_edge(const Point3& s0, const Point3& s1, const Point3& p, const Point3& q) const {
        return triangles_meet_beyond_edge(s0, s1, p, q);
    }
};

/// No exact test: what the proof leaves open counts as meeting.
struct Assumed {
    bool meet(const Triangle3&, const Triangle3&) const { return true; }
    bool meet_beyond_corner(const Triangle3&, const Triangle3&) const { return true; }
    bool meet_beyond_edge(const Point3&, const Point3&, const Point3&, const Point3&) const { return true; }
};

/// The dispatch by shared corners: false when @a proof proves the triangles apart for that
/// case, else @a test's answer.
template <class Proof, class Test>
bool meet_beyond_shared(const Ids& t_ids, const Triangle3& t, const Ids& u_ids, const Triangle3& u, const Proof& proof, const Test& test) {
    int shared = 0, t_shared = -1, u_shared = -1;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (t_ids[i] != u_ids[j]) continue;
            if (shared == 0) t_shared = i, u_shared = j;
            ++shared;
        }
    }
    switch (shared) {
        case 0: return !proof.apart() && test.meet(t, u);
        case 1: return !proof.apart_beyond_corner(t_shared, u_shared) && test.meet_beyond_corner(rotated(t, t_shared), rotated(u, u_shared));
        case 2: {
            // t runs s0 -> s1 -> apex; u shares the edge the other way.
            int t_apex = 0, u_apex = 0;
            while (shares(t_ids[t_apex], u_ids)) ++t_apex;
            while (shares(u_ids[u_apex], t_ids)) ++u_apex;
            const Point3 &s0 = t[(t_apex + 1) % 3], &s1 = t[(t_apex + 2) % 3];
            return !proof.apart_beyond_edge(s0, s1, t[t_apex], u[u_apex]) && test.meet_beyond_edge(s0, s1, t[t_apex], u[u_apex]);
        }
        default: return true;  // the same three points: a duplicated face
    }
}

}  // namespace

bool triangles_intersect(const Ids& t_ids, const Triangle3& t, const Ids& u_ids, const Triangle3& u) {
    return meet_beyond_shared(t_ids, t, u_ids, u, Unproven{}, Exact{});
}

bool triangles_intersect(const Ids& t_ids, const PreparedTriangle& t, const Ids& u_ids, const PreparedTriangle& u) {
    return meet_beyond_shared(t_ids, t.corners, u_ids, u.corners, Proven{t, u}, Exact{});
}

bool proven_apart(const Ids& t_ids, const PreparedTriangle& t, const Ids& u_ids, const PreparedTriangle& u) {
    return !meet_beyond_shared(t_ids, t.corners, u_ids, u.corners, Proven{t, u}, Assumed{});
}

}  // namespace vdbmesh::detail
