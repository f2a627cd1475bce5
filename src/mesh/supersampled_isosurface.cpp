// The reference surface of `vdbmesh compare`: the grid resampled at half the voxel size by its
// own trilinear interpolant, then meshed by Marching Cubes. MC vertices lie on the
// interpolant's isosurface along every fine edge, and the fine triangles deviate from it by
// about (cell / 2)^2 * curvature / 8, so samples on this mesh stand for samples on the
// trilinear isosurface. Also: moving meshes to index space, where distances are in voxels.
//
// Resampling keeps the tree's sparsity: a coarse leaf (8^3 voxels at origin o) becomes the 8
// fine leaves of 16^3 voxels at 2o, filled in parallel; coarse tiles become fine tiles of
// twice the extent, so the classification of every fine sample matches its coarse region.

#include <tbb/parallel_for.h>

#include <vector>

#include "mesh/trilinear_field.h"
#include "vdbmesh/compare.h"
#include "vdbmesh/grid.h"

namespace vdbmesh {
namespace {

using LeafT = openvdb::FloatTree::LeafNodeType;
constexpr int kLeafDim = int(LeafT::DIM);

/// The 8 fine leaves of one coarse leaf: fine voxel f holds the interpolant at f / 2 and is
/// active when coarse voxel floor(f / 2) is.
std::vector<LeafT*> fine_leaves(const openvdb::FloatGrid& grid, const LeafT& coarse, float background) {
    const detail::TrilinearField field(grid);
    std::vector<LeafT*> leaves;
    const openvdb::Coord origin = coarse.origin();
    for (int c = 0; c < 8; ++c) {
        const openvdb::Coord fine_origin(2 * origin[0] + kLeafDim * (c & 1), 2 * origin[1] + kLeafDim * ((c >> 1) & 1),
                                         2 * origin[2] + kLeafDim * ((c >> 2) & 1));
        auto* leaf = new LeafT(fine_origin, background, false);
        for (auto it = leaf->beginValueAll(); it; ++it) {
            const openvdb::Coord f = it.getCoord();
            it.setValue(float(field(openvdb::Vec3d(f[0], f[1], f[2]) * 0.5).value));
            const openvdb::Coord v(f[0] >> 1, f[1] >> 1, f[2] >> 1);
            it.setValueOn(coarse.isValueOn(v));
        }
        leaves.push_back(leaf);
    }
    return leaves;
}

openvdb::Coord doubled(const openvdb::Coord& c) { return openvdb::Coord(2 * c[0], 2 * c[1], 2 * c[2]); }

openvdb::FloatGrid::Ptr supersample(const openvdb::FloatGrid& grid) {
    const float background = grid.background();
    auto fine = openvdb::FloatGrid::create(background);
    fine->setTransform(openvdb::math::Transform::createLinearTransform(0.5));  // fine index -> coarse index
    for (auto it = grid.tree().cbeginValueAll(); it; ++it) {
        if (it.isVoxelValue()) continue;
        openvdb::CoordBBox box;
        it.getBoundingBox(box);
        if (it.getValue() == background) continue;
        fine->tree().fill(openvdb::CoordBBox(doubled(box.min()), doubled(box.max()) + openvdb::Coord(1)), it.getValue(),
                          it.isValueOn());
    }
    std::vector<const LeafT*> coarse;
    for (auto it = grid.tree().cbeginLeaf(); it; ++it) coarse.push_back(&*it);
    std::vector<std::vector<LeafT*>> made(coarse.size());
    tbb::parallel_for(std::size_t(0), coarse.size(), [&](std::size_t i) { made[i] = fine_leaves(grid, *coarse[i], background); });
    for (auto& leaves : made)
        for (LeafT* leaf : leaves) fine->tree().addLeaf(leaf);  // the tree takes ownership
    const auto min = grid.getMetadata<openvdb::Vec3IMetadata>(kMetaScanMin);
    const auto max = grid.getMetadata<openvdb::Vec3IMetadata>(kMetaScanMax);
    if (min && max) {
        fine->insertMeta(kMetaScanMin, openvdb::Vec3IMetadata(min->value() * 2));
        fine->insertMeta(kMetaScanMax, openvdb::Vec3IMetadata(max->value() * 2));
    }
    return fine;
}

}  // namespace

Mesh supersampled_isosurface(const openvdb::FloatGrid& grid, double iso, Inside inside) {
    const openvdb::FloatGrid::Ptr fine = supersample(grid);
    MeshOptions options;
    options.method = MeshMethod::mc;
    options.iso = iso;
    options.inside = inside;
    return mesh_grid(*fine, options);
}

Mesh to_index_space(const Mesh& mesh, const openvdb::FloatGrid& grid) {
    Mesh moved = mesh;
    const openvdb::math::Transform& transform = grid.transform();
    tbb::parallel_for(std::size_t(0), moved.vertices.size(), [&](std::size_t i) {
        auto& v = moved.vertices[i];
        const openvdb::Vec3d p = transform.worldToIndex(openvdb::Vec3d(v[0], v[1], v[2]));
        v = {float(p[0]), float(p[1]), float(p[2])};
    });
    return moved;
}

}  // namespace vdbmesh
