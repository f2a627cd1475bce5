#include "view/coarse_grid.h"

#include <openvdb/tools/Dense.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "vdbmesh/grid.h"

namespace vdbmesh::view {

namespace {

using DenseGrid = openvdb::tools::Dense<float, openvdb::tools::LayoutXYZ>;

openvdb::Coord coarse_dims(const openvdb::CoordBBox& box, int factor) {
    const openvdb::Coord dims = box.dim();
    return {(dims.x() + factor - 1) / factor, (dims.y() + factor - 1) / factor, (dims.z() + factor - 1) / factor};
}

/// The mean of the full samples in the block of coarse voxel @a coarse.
template <typename Accessor>
float block_mean(const Accessor& full, const openvdb::CoordBBox& box, int factor, const openvdb::Coord& coarse) {
    const openvdb::Coord first = box.min() + openvdb::Coord(coarse.x() * factor, coarse.y() * factor, coarse.z() * factor);
    const openvdb::Coord last = openvdb::Coord::minComponent(first + openvdb::Coord(factor - 1), box.max());
    double sum = 0;
    int count = 0;
    for (int z = first.z(); z <= last.z(); ++z) {
        for (int y = first.y(); y <= last.y(); ++y) {
            for (int x = first.x(); x <= last.x(); ++x, ++count) sum += full.getValue(openvdb::Coord(x, y, z));
        }
    }
    return float(sum / count);
}

/// The coarse layers [first_layer, end_layer) of @a dense from @a grid, in parallel by rows
/// (a single layer is shared by the threads too).
void fill_dense(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box, int factor, DenseGrid& dense,
                int first_layer, int end_layer) {
    const openvdb::Coord dims = dense.bbox().dim();
    tbb::parallel_for(tbb::blocked_range2d<int>(first_layer, end_layer, 0, dims.y()), [&](const tbb::blocked_range2d<int>& rows) {
        const auto full = grid.getConstAccessor();
        for (int z = rows.rows().begin(); z < rows.rows().end(); ++z) {
            for (int y = rows.cols().begin(); y < rows.cols().end(); ++y) {
                for (int x = 0; x < dims.x(); ++x) {
                    const openvdb::Coord coarse(x, y, z);
                    dense.setValue(coarse, block_mean(full, box, factor, coarse));
                }
            }
        }
    });
}

/// The full grid's transform with index space scaled by @a factor and shifted to the centre
/// of the block at box.min(): coarse c maps where full box.min() + factor * c + (factor - 1) / 2 does.
openvdb::math::Transform::Ptr coarse_transform(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box,
                                               int factor) {
    auto transform = grid.transform().copy();
    const openvdb::Vec3d block_centre = box.min().asVec3d() + openvdb::Vec3d(0.5 * (factor - 1));
    transform->preScale(double(factor));
    transform->preTranslate(block_centre / double(factor));
    return transform;
}

}  // namespace

int coarse_factor(const openvdb::CoordBBox& box, std::int64_t max_samples) {
    int factor = 1;
    auto samples = [&] {
        const openvdb::Coord dims = coarse_dims(box, factor);
        return std::int64_t(dims.x()) * dims.y() * dims.z();
    };
    while (samples() > max_samples) ++factor;
    return factor;
}

namespace {

/// The coarse grid of @a dense, placed and named after @a grid (its description suffices).
openvdb::FloatGrid::Ptr coarse_from_dense(const DenseGrid& dense, const openvdb::FloatGrid& grid,
                                          const openvdb::CoordBBox& box, int factor) {
    const openvdb::Coord dims = dense.bbox().dim();
    auto coarse = openvdb::FloatGrid::create(grid.background());
    openvdb::tools::copyFromDense(dense, coarse->tree(), 0.0f);
    coarse->setTransform(coarse_transform(grid, box, factor));
    coarse->setName(grid.getName());
    coarse->insertMeta(kMetaScanMin, openvdb::Vec3IMetadata(openvdb::Vec3i(0, 0, 0)));
    coarse->insertMeta(kMetaScanMax, openvdb::Vec3IMetadata(openvdb::Vec3i(dims.x() - 1, dims.y() - 1, dims.z() - 1)));
    return coarse;
}

}  // namespace

openvdb::FloatGrid::Ptr coarse_grid(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box, int factor) {
    DenseGrid dense(openvdb::CoordBBox(openvdb::Coord(0), coarse_dims(box, factor) - openvdb::Coord(1)));
    fill_dense(grid, box, factor, dense, 0, dense.bbox().dim().z());
    return coarse_from_dense(dense, grid, box, factor);
}

openvdb::FloatGrid::Ptr coarse_grid(const GridRegionSource& source, const openvdb::CoordBBox& box, int factor,
                                    const SlabVisitor& visit, const Checkpoint& checkpoint) {
    DenseGrid dense(openvdb::CoordBBox(openvdb::Coord(0), coarse_dims(box, factor) - openvdb::Coord(1)));
    const int layers = dense.bbox().dim().z();
    // Slabs of whole coarse layers about one node thick, read one at a time.
    const int slab_layers = std::max(1, kNodeVoxels / factor);
    for (int first = 0; first < layers; first += slab_layers) {
        const int end = std::min(layers, first + slab_layers);
        IndexBox slab;
        for (int a = 0; a < 3; ++a) {
            slab.min[a] = box.min()[a];
            slab.max[a] = box.max()[a] + 1;
        }
        slab.min[2] = box.min().z() + first * factor;
        slab.max[2] = std::min(box.max().z() + 1, box.min().z() + end * factor);
        const auto slab_grid = source.read(slab);
        for (int layer = first; layer < end; ++layer) {
            checkpoint();
            fill_dense(*slab_grid, box, factor, dense, layer, layer + 1);
        }
        visit(*slab_grid, openvdb::CoordBBox(openvdb::Coord(box.min().x(), box.min().y(), slab.min[2]),
                                             openvdb::Coord(box.max().x(), box.max().y(), slab.max[2] - 1)));
    }
    return coarse_from_dense(dense, *source.description(), box, factor);
}

}  // namespace vdbmesh::view
