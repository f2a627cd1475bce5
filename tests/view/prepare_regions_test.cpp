// prepare_grid_regions() of a converted grid: the histogram is counted in the pass that makes
// the statistics and the coarse grid when the grid states its value range truly, and in a
// second pass when it does not; either way it is what the grid held whole gives (prepare_grid()).

#include <gtest/gtest.h>

#include <atomic>

#include "phantom_grid.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/phantom.h"
#include "vdbmesh/view.h"

namespace vdbmesh {
namespace {

/// A source that counts its reads.
class CountingRegions : public GridRegionSource {
public:
    explicit CountingRegions(std::unique_ptr<GridRegionSource> source) : source_(std::move(source)) {}
    std::shared_ptr<const openvdb::FloatGrid> description() const override { return source_->description(); }
    std::vector<NodeWeight> nodes() const override { return source_->nodes(); }
    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox& box) const override {
        ++reads;
        return source_->read(box);
    }
    std::uint64_t estimated_bytes(const IndexBox& box) const override { return source_->estimated_bytes(box); }
    mutable std::atomic<int> reads{0};

private:
    std::unique_ptr<GridRegionSource> source_;
};

/// prepare_grid_regions() of @a grid written with the value range @a stated in its metadata;
/// @a reads: how many regions it read.
ViewScan prepared_stating(const openvdb::FloatGrid& grid, std::pair<double, double> stated, int& reads) {
    const auto copy = openvdb::gridPtrCast<openvdb::FloatGrid>(grid.copyGridWithNewTree());
    copy->setTree(grid.constTreePtr()->copy());
    copy->insertMeta(kMetaValueMin, openvdb::DoubleMetadata(stated.first));
    copy->insertMeta(kMetaValueMax, openvdb::DoubleMetadata(stated.second));
    test::ScratchDir dir;
    write_vdb(*copy, dir / "grid.vdb");
    auto counting = std::make_shared<CountingRegions>(open_vdb_regions(dir / "grid.vdb"));
    ViewScan scan = prepare_grid_regions(counting);
    reads = counting->reads;
    return scan;
}

TEST(PrepareRegions, AStatedValueRangeSavesTheHistogramsPassOnlyWhenTrue) {
    PhantomSpec spec = phantom_preset("cylinder", {300, 48, 60});
    spec.radius = 17;
    spec.height = 280;
    spec.rotation_degrees = {0, 90, 0};
    const auto grid = test::phantom_scan_grid(spec);
    const ViewScan whole = prepare_grid(grid);
    const std::pair<double, double> truth{whole.histogram.min, whole.histogram.max};
    int true_reads = 0, false_reads = 0;
    const ViewScan trusted = prepared_stating(*grid, truth, true_reads);
    const ViewScan checked = prepared_stating(*grid, {truth.first - 1, truth.second + 1}, false_reads);
    for (const ViewScan* scan : {&trusted, &checked}) {
        EXPECT_EQ(scan->histogram.min, whole.histogram.min);
        EXPECT_EQ(scan->histogram.max, whole.histogram.max);
        EXPECT_EQ(scan->histogram.counts, whole.histogram.counts);
        EXPECT_EQ(scan->suggested_iso, whole.suggested_iso);
    }
    EXPECT_GT(true_reads, 0);
    EXPECT_LT(true_reads, false_reads);  // one pass, not two
}

TEST(PrepareRegions, AStoppedPreparationGivesUpBeforeItsNextRead) {
    const auto grid = test::phantom_scan_grid(phantom_preset("sphere", {40, 40, 40}));
    auto counting = std::make_shared<CountingRegions>(grid_regions_in_memory(grid));
    BackgroundControl control;
    const ViewScan scan = prepare_grid_regions(counting, &control);
    EXPECT_EQ(scan.regions, counting);  // the source itself, not the stoppable wrapper
    const int whole = counting->reads;
    EXPECT_GT(whole, 0);
    control.stop();  // a server closing while it prepares
    try {
        prepare_grid_regions(counting, &control);
        ADD_FAILURE() << "no error once stopped";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("stopped"), std::string::npos) << e.what();
    }
    EXPECT_EQ(counting->reads, whole);  // not one read more
}

}  // namespace
}  // namespace vdbmesh
