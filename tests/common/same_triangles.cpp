#include "same_triangles.h"

#include <algorithm>
#include <array>
#include <set>

namespace vdbmesh::test {

namespace {

using Corner = std::array<float, 3>;

std::set<std::array<Corner, 3>> triangle_set(const Mesh& mesh) {
    std::set<std::array<Corner, 3>> set;
    for (const auto& t : mesh.triangles) {
        std::array<Corner, 3> c = {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
        // Rotate so the smallest corner comes first (keeps the orientation).
        std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
        set.insert(c);
    }
    return set;
}

}  // namespace

bool same_triangles(const Mesh& a, const Mesh& b) {
    return a.vertices.size() == b.vertices.size() && a.triangles.size() == b.triangles.size() &&
           std::set<Corner>(a.vertices.begin(), a.vertices.end()) == std::set<Corner>(b.vertices.begin(), b.vertices.end()) &&
           triangle_set(a) == triangle_set(b);
}

}  // namespace vdbmesh::test
