// Dual cells of the leaf octrees, enumerated per leaf without recursion (Schaefer and Warren,
// "Dual Marching Cubes: Primal Contouring of Dual Grids", Pacific Graphics 2004, section 4,
// made flat: see dmc_dual_cells.h). The cell holding voxel p + delta has p + 1/2 as a corner
// iff its size divides p + 1 on every axis (cells are aligned to their size).

#include "mesh/dmc_dual_cells.h"

namespace vdbmesh::detail {

namespace {

bool is_corner_of(const DualCorner& corner, const openvdb::Coord& p) {
    const int mask = corner.size - 1;
    return ((p.x() + 1) & mask) == 0 && ((p.y() + 1) & mask) == 0 && ((p.z() + 1) & mask) == 0;
}

/// Whether leaf @a leaf owns the dual cell at local voxel corner (x, y, z) + 1/2, x, y, z in
/// [-1, 7]: inside the leaf always; on the ring below it only when a tile holds voxel p and
/// this leaf is the first (in corner order) holding one of the 8 voxels.
bool owns_dual_cell(const DmcGrid& grid, std::size_t leaf, int x, int y, int z) {
    if (x >= 0 && y >= 0 && z >= 0) return true;
    for (int c = 0; c < 8; ++c) {
        const std::int32_t holder = grid.leaf_at(leaf, x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2));
        if (holder >= 0) return holder == std::int32_t(leaf);
    }
    return false;
}

}  // namespace

DualCorner sample_corner(const SampleBlock& block, int x, int y, int z) {
    DualCorner corner;
    corner.min = block.origin.offsetBy(x, y, z);
    corner.position = {double(corner.min.x()), double(corner.min.y()), double(corner.min.z())};
    corner.value = block.at(x, y, z);
    return corner;
}

DualCorner dual_corner(const DmcGrid& grid, const std::vector<LeafOctree>& octrees, std::size_t leaf,
                       const SampleBlock& block, int x, int y, int z) {
    const std::int32_t holder = grid.leaf_at(leaf, x, y, z);
    const int level = holder < 0 ? 0 : octrees[std::size_t(holder)].level_at(leaf_offset(x & 7, y & 7, z & 7));
    if (level == 0) return sample_corner(block, x, y, z);
    DualCorner corner;
    const int mask = ~((1 << level) - 1);
    const int mx = (x & 7) & mask, my = (y & 7) & mask, mz = (z & 7) & mask;
    const CellVertex& vertex = octrees[std::size_t(holder)].vertex_at(leaf_offset(mx, my, mz));
    corner.min = grid.leaves[std::size_t(holder)]->origin().offsetBy(mx, my, mz);
    corner.size = 1 << level;
    corner.position = vertex.position;
    corner.value = vertex.value;
    return corner;
}

void collect_dual_cells(const DmcGrid& grid, const std::vector<LeafOctree>& octrees, std::size_t leaf,
                        const SampleBlock& block, std::vector<DualCell>& cells) {
    const bool merged = neighbourhood_has_merges(grid, octrees, leaf);
    const bool ring_possible = grid.neighbours[leaf][neighbour_slot(-1, 0, 0)] < 0 ||
                               grid.neighbours[leaf][neighbour_slot(0, -1, 0)] < 0 ||
                               grid.neighbours[leaf][neighbour_slot(0, 0, -1)] < 0;
    const int first = ring_possible ? -1 : 0;
    // Side of the vertex of the cell holding each voxel of the block: without merges, the
    // sample's side. Dual cells without a sign change are skipped before any other lookup.
    std::array<bool, SampleBlock::kDim * SampleBlock::kDim * SampleBlock::kDim> cell_inside = block.inside;
    // With merges, the cell of every voxel of the block, looked up once.
    std::vector<DualCorner> corner_of;
    if (merged) {
        corner_of.resize(cell_inside.size());
        for (int x = -1; x <= kLeafDim; ++x) {
            for (int y = -1; y <= kLeafDim; ++y) {
                for (int z = -1; z <= kLeafDim; ++z) {
                    const std::size_t i = std::size_t(SampleBlock::index(x, y, z));
                    corner_of[i] = dual_corner(grid, octrees, leaf, block, x, y, z);
                    cell_inside[i] = grid.inside(corner_of[i].value);
                }
            }
        }
    }
    for (int x = first; x < kLeafDim; ++x) {
        for (int y = first; y < kLeafDim; ++y) {
            for (int z = first; z < kLeafDim; ++z) {
                DualCell cell;
                cell.config = 0;
                for (int c = 0; c < 8; ++c) {
                    cell.config |= unsigned(cell_inside[std::size_t(SampleBlock::index(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2)))]) << c;
                }
                if (cell.config == 0 || cell.config == 255) continue;
                if ((x < 0 || y < 0 || z < 0) && !owns_dual_cell(grid, leaf, x, y, z)) continue;
                cell.p = block.origin.offsetBy(x, y, z);
                if (grid.open_boundary && grid.scan_box &&
                    !(grid.scan_box->isInside(cell.p) && grid.scan_box->isInside(cell.p.offsetBy(1)))) {
                    continue;
                }
                bool emitted = !merged;
                for (int c = 0; c < 8; ++c) {
                    DualCorner& corner = cell.corners[std::size_t(c)];
                    const int cx = x + (c & 1), cy = y + ((c >> 1) & 1), cz = z + (c >> 2);
                    corner = merged ? corner_of[std::size_t(SampleBlock::index(cx, cy, cz))] : sample_corner(block, cx, cy, cz);
                    emitted = emitted || is_corner_of(corner, cell.p);
                }
                if (emitted) cells.push_back(cell);
            }
        }
    }
}

}  // namespace vdbmesh::detail
