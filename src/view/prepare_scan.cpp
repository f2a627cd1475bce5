// prepare_scan(), prepare_grid() and prepare_grid_regions(): a scan or a stored grid made
// ready for live re-meshing.

#include <algorithm>
#include <optional>
#include <utility>

#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/view.h"
#include "vdbmesh/volume_stats.h"
#include "view/coarse_grid.h"
#include "view/grid_samples.h"
#include "view/controlled_regions.h"

namespace vdbmesh {

namespace {

ViewScan finish_view_scan(openvdb::FloatGrid::Ptr grid, const openvdb::CoordBBox& box, const VolumeStats& stats) {
    ViewScan scan;
    scan.regions = grid_regions_in_memory(grid);
    scan.histogram = view::sample_histogram(*grid, box, stats.min, stats.max, kViewHistogramBins);
    scan.suggested_iso = stats.suggested_iso;
    scan.suggested_reason = stats.suggested_reason;
    scan.coarse_factor = view::coarse_factor(box, kCoarseSampleBudget);
    scan.coarse = view::coarse_grid(*grid, box, scan.coarse_factor);
    scan.grid = std::move(grid);
    return scan;
}

/// Calls @a visit with each slab of @a box about one node thick (z-ordered) and the grid read
/// for it from @a source.
void for_each_slab(const GridRegionSource& source, const openvdb::CoordBBox& box, const view::SlabVisitor& visit) {
    for (int z = box.min().z(); z <= box.max().z(); z += kNodeVoxels) {
        const openvdb::CoordBBox slab(openvdb::Coord(box.min().x(), box.min().y(), z),
                                      openvdb::Coord(box.max().x(), box.max().y(), std::min(box.max().z(), z + kNodeVoxels - 1)));
        IndexBox read_box{{slab.min().x(), slab.min().y(), slab.min().z()}, {slab.max().x() + 1, slab.max().y() + 1, slab.max().z() + 1}};
        visit(*source.read(read_box), slab);
    }
}

/// The box of @a source's nodes.
openvdb::CoordBBox nodes_box(const GridRegionSource& source) {
    openvdb::CoordBBox box;
    for (const NodeWeight& node : source.nodes()) {
        const openvdb::Coord origin(node.origin[0], node.origin[1], node.origin[2]);
        box.expand(openvdb::CoordBBox(origin, origin.offsetBy(kNodeVoxels - 1)));
    }
    return box;
}

/// The range of a converted grid's samples as far as its description tells: the scan's values
/// its metadata states (kMetaValueMin/Max) and the background (the converter's value outside
/// the surface's band lies beyond them). None without the metadata.
std::optional<std::pair<double, double>> stated_value_range(const openvdb::FloatGrid& grid) {
    const auto low = grid.getMetadata<openvdb::DoubleMetadata>(kMetaValueMin);
    const auto high = grid.getMetadata<openvdb::DoubleMetadata>(kMetaValueMax);
    if (!low || !high) return std::nullopt;
    const double background = grid.background();
    const std::pair<double, double> range{std::min(low->value(), background), std::max(high->value(), background)};
    if (!(range.first < range.second)) return std::nullopt;
    return range;
}

}  // namespace

ViewScan prepare_scan(const std::function<std::unique_ptr<VolumeReader>()>& open_reader) {
    const VolumeStats stats = compute_volume_stats(*open_reader());
    ConvertOptions convert;
    convert.iso_range = std::make_pair(stats.min, stats.max);
    auto grid = convert_to_grid(*open_reader(), convert);
    const openvdb::CoordBBox box = stored_scan_box(*grid).value();
    return finish_view_scan(std::move(grid), box, stats);
}

ViewScan prepare_grid(std::shared_ptr<openvdb::FloatGrid> grid) {
    const openvdb::CoordBBox box = stored_scan_box(*grid).value_or(grid->evalActiveVoxelBoundingBox());
    VolumeStatsAccumulator accumulator;
    view::for_each_sample(*grid, box, [&](const float* values, std::size_t count) { accumulator.add(values, count); });
    return finish_view_scan(std::move(grid), box, accumulator.finish());
}

namespace {

/// prepare_grid_regions() reading through @a source, @a checkpoint called between reads and
/// between the pieces of each slab's work (a coarse layer, a run of 512 samples); the scan's
/// regions left unset.
ViewScan prepare_by_slabs(const GridRegionSource& source, const view::Checkpoint& checkpoint) {
    const auto description = source.description();
    const openvdb::CoordBBox box = stored_scan_box(*description).value_or(nodes_box(source));
    if (box.empty()) throw Error("the grid holds no active voxels");
    // The histogram's bins span the samples' range. A converted grid states it: the histogram
    // is then counted in the same pass as the statistics and the coarse grid, and kept when the
    // samples' range is the one stated (the samples are read once, not twice). Otherwise a
    // second pass counts it.
    const auto stated = stated_value_range(*description);
    ValueHistogram histogram;
    if (stated) histogram = ValueHistogram{stated->first, stated->second, std::vector<std::uint64_t>(kViewHistogramBins, 0)};
    VolumeStatsAccumulator accumulator;
    ViewScan scan;
    scan.coarse_factor = view::coarse_factor(box, kCoarseSampleBudget);
    scan.coarse = view::coarse_grid(source, box, scan.coarse_factor, [&](const openvdb::FloatGrid& slab_grid, const openvdb::CoordBBox& slab) {
        view::for_each_sample(slab_grid, slab, [&](const float* values, std::size_t count) {
            checkpoint();
            accumulator.add(values, count);
            if (stated) view::add_samples(histogram, values, count);
        });
    }, checkpoint);
    const VolumeStats stats = accumulator.finish();
    if (stated && stats.min == stated->first && stats.max == stated->second) {
        scan.histogram = std::move(histogram);
    } else {
        scan.histogram = ValueHistogram{stats.min, stats.max, std::vector<std::uint64_t>(kViewHistogramBins, 0)};
        for_each_slab(source, box, [&](const openvdb::FloatGrid& slab_grid, const openvdb::CoordBBox& slab) {
            view::for_each_sample(slab_grid, slab, [&](const float* values, std::size_t count) {
                checkpoint();
                view::add_samples(scan.histogram, values, count);
            });
        });
    }
    scan.suggested_iso = stats.suggested_iso;
    scan.suggested_reason = stats.suggested_reason;
    return scan;
}

}  // namespace

constexpr const char* kPreparation = "the scan's preparation";

ViewScan prepare_grid_regions(std::shared_ptr<const GridRegionSource> regions, const BackgroundControl* control) {
    ViewScan scan;
    if (control) {
        const view::ControlledRegions controlled(regions, *control, kPreparation);
        scan = prepare_by_slabs(controlled, [control] { control->checkpoint(kPreparation); });
    } else {
        scan = prepare_by_slabs(*regions, [] {});
    }
    scan.regions = std::move(regions);
    return scan;
}

}  // namespace vdbmesh
