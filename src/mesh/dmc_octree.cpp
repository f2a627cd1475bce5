// Leaf octrees for Dual Marching Cubes.

#include "mesh/dmc_octree.h"

namespace vdbmesh::detail {

void LeafOctree::split_cell(int offset) {
    (void)offset;
}

std::vector<LeafOctree> build_leaf_octrees(const DmcGrid& grid, double error) {
    (void)error;
    return std::vector<LeafOctree>(grid.leaves.size());
}

}  // namespace vdbmesh::detail
