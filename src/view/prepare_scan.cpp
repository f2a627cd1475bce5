// prepare_scan() and prepare_grid(): a scan or a stored grid made ready for live re-meshing.

#include <utility>

#include "vdbmesh/grid.h"
#include "vdbmesh/view.h"
#include "vdbmesh/volume_stats.h"
#include "view/coarse_grid.h"
#include "view/grid_samples.h"

namespace vdbmesh {

namespace {

ViewScan finish_view_scan(openvdb::FloatGrid::Ptr grid, const openvdb::CoordBBox& box, const VolumeStats& stats) {
    ViewScan scan;
    scan.histogram = view::sample_histogram(*grid, box, stats.min, stats.max, kViewHistogramBins);
    scan.suggested_iso = stats.suggested_iso;
    scan.suggested_reason = stats.suggested_reason;
    scan.coarse_factor = view::coarse_factor(box, kCoarseSampleBudget);
    scan.coarse = view::coarse_grid(*grid, box, scan.coarse_factor);
    scan.grid = std::move(grid);
    return scan;
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

}  // namespace vdbmesh
