// The edge groups of Marching Cubes cells (dual_surface_groups.h), made once from the case table.

#include "mesh/dual_surface_groups.h"

#include <numeric>

#include "mesh/mc_table.h"

namespace vdbmesh::detail {

namespace {

CellGroups groups_of(unsigned config) {
    std::array<int, 12> parent;
    std::iota(parent.begin(), parent.end(), 0);
    const auto root = [&](int e) {
        while (parent[e] != e) e = parent[e] = parent[parent[e]];
        return e;
    };
    const McCase& cell_case = mc_case(config);
    std::array<bool, 12> crossed{};
    for (int t = 0; t < cell_case.triangle_count; ++t) {
        for (int k = 0; k < 3; ++k) {
            crossed[cell_case.triangles[t][k]] = true;
            parent[root(cell_case.triangles[t][k])] = root(cell_case.triangles[t][0]);
        }
    }
    CellGroups groups;
    groups.of_edge.fill(-1);
    std::array<int, 12> group_of_root;
    group_of_root.fill(-1);
    for (int e = 0; e < 12; ++e) {  // groups numbered by their lowest edge
        if (!crossed[e]) continue;
        int& group = group_of_root[root(e)];
        if (group < 0) group = groups.count++;
        groups.of_edge[e] = std::int8_t(group);
        groups.rank[e] = groups.size[group]++;
    }
    return groups;
}

}  // namespace

const CellGroups& cell_groups(unsigned config) {
    static const std::array<CellGroups, 256> table = [] {
        std::array<CellGroups, 256> all;
        for (unsigned c = 0; c < 256; ++c) all[c] = groups_of(c);
        return all;
    }();
    return table[config];
}

int cell_edge(unsigned corner, int axis) {
    static const std::array<std::array<std::int8_t, 3>, 8> table = [] {
        std::array<std::array<std::int8_t, 3>, 8> edges{};
        for (auto& row : edges) row.fill(-1);
        for (int e = 0; e < 12; ++e) {
            const unsigned a = kEdgeCorners[e][0], b = kEdgeCorners[e][1];
            edges[a][(a ^ b) == 1 ? 0 : (a ^ b) == 2 ? 1 : 2] = std::int8_t(e);
        }
        return edges;
    }();
    return table[corner][axis];
}

}  // namespace vdbmesh::detail
