#include "view/grid_samples.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vdbmesh::view {

namespace {

constexpr std::size_t kRun = openvdb::FloatTree::LeafNodeType::SIZE;

void visit_leaves(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box, const SampleRunVisitor& visit) {
    std::array<float, kRun> run;
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
        std::size_t count = 0;
        for (auto voxel = leaf->cbeginValueAll(); voxel; ++voxel) {
            if (box.isInside(voxel.getCoord())) run[count++] = *voxel;
        }
        if (count > 0) visit(run.data(), count);
    }
}

void visit_tiles(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box, const SampleRunVisitor& visit) {
    std::array<float, kRun> run;
    auto tile = grid.tree().cbeginValueAll();
    tile.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);
    for (; tile; ++tile) {
        openvdb::CoordBBox inside;
        tile.getBoundingBox(inside);
        inside.intersect(box);
        if (inside.empty()) continue;
        run.fill(*tile);
        for (openvdb::Index64 left = inside.volume(); left > 0;) {
            const std::size_t count = std::size_t(std::min<openvdb::Index64>(left, kRun));
            visit(run.data(), count);
            left -= count;
        }
    }
}

}  // namespace

void for_each_sample(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box, const SampleRunVisitor& visit) {
    visit_leaves(grid, box, visit);
    visit_tiles(grid, box, visit);
}

void add_samples(ValueHistogram& histogram, const float* values, std::size_t count) {
    const std::size_t bins = histogram.counts.size();
    const double min = histogram.min, max = histogram.max;
    const double scale = max > min ? double(bins) / (max - min) : 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        const double bin = std::floor((values[i] - min) * scale);
        histogram.counts[std::size_t(std::clamp(bin, 0.0, double(bins - 1)))] += 1;
    }
}

ValueHistogram sample_histogram(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box, double min, double max,
                                std::size_t bins) {
    ValueHistogram histogram{min, max, std::vector<std::uint64_t>(bins, 0)};
    for_each_sample(grid, box, [&](const float* values, std::size_t count) { add_samples(histogram, values, count); });
    return histogram;
}

}  // namespace vdbmesh::view
