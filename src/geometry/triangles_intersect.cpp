// triangles_intersect(): which exact test of triangle_intersection.cpp applies to a pair of
// triangles, by the corners they share.
#include "geometry/triangle_intersection.h"
#include "vdbmesh/geometry.h"

namespace vdbmesh::detail {
namespace {

/// The triangle's corners starting from corner @a first (a rotation: same orientation).
Triangle3 rotated(const Triangle3& t, int first) { return {t[first], t[(first + 1) % 3], t[(first + 2) % 3]}; }

bool shares(std::uint32_t id, const std::array<std::uint32_t, 3>& ids) { return id == ids[0] || id == ids[1] || id == ids[2]; }

}  // namespace

bool triangles_intersect(const std::array<std::uint32_t, 3>& t_ids, const Triangle3& t,
                         const std::array<std::uint32_t, 3>& u_ids, const Triangle3& u) {
    int shared = 0, t_shared = -1, u_shared = -1;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (t_ids[i] != u_ids[j]) continue;
            if (shared == 0) t_shared = i, u_shared = j;
            ++shared;
        }
    }
    switch (shared) {
        case 0: return triangles_meet(t, u);
        case 1: return triangles_meet_beyond_corner(rotated(t, t_shared), rotated(u, u_shared));
        case 2: {
            int t_apex = 0, u_apex = 0;
            while (shares(t_ids[t_apex], u_ids)) ++t_apex;
            while (shares(u_ids[u_apex], t_ids)) ++u_apex;
            return triangles_meet_beyond_edge(t[(t_apex + 1) % 3], t[(t_apex + 2) % 3], t[t_apex], u[u_apex]);
        }
        default: return true;  // the same three points: a duplicated face
    }
}

}  // namespace vdbmesh::detail
