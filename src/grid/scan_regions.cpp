// A scan read by region, straight from its file: convert_to_grid()'s conversion made row by
// row (converter.h), a band of rows at a time.
//
// Opening surveys the whole scan once: every row is made and dropped, keeping the sample range
// (the background and the metadata depend on it) and each node's count of active voxels
// (nodes()). That costs a conversion's time and its slice windows, never the grid.
// read(box) then needs the rows of leaves that meet the box in z (the whole x and y extent:
// the band); the band last made is kept, so the bricks of one z-layer, visited one after the
// other, share it. A band that follows the last goes on with the same converter (rows both
// share are copied from the last band); a band that lies before it (reads out of z order)
// reopens the scan and skips to it. Each row is made from samples within band + 1 slices of
// it, so it equals the whole conversion's row, and so the band equals the whole grid there.

#include <tbb/task_arena.h>

#include <map>
#include <mutex>
#include <tuple>

#include "converter.h"
#include "region_walk.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/scan_regions.h"

namespace vdbmesh {

namespace {

using detail::ConvertedRow;
using detail::Converter;
using detail::kLeafDim;
using detail::region_walk::Leaf;
using detail::region_walk::TreeRegion;

/// A scan being converted from some row on: its reader and the converter reading it.
struct Conversion {
    std::unique_ptr<SliceReader> reader;
    std::unique_ptr<Converter> converter;
    int next_row = 0;  ///< the row make_row() makes next
};

/// What the survey of the whole scan found.
struct Survey {
    detail::ScanValues values;
    std::vector<NodeWeight> nodes;      ///< z-major
    std::map<int, std::uint64_t> leaves;  ///< per row (z0) with leaves: how many
    std::shared_ptr<const openvdb::FloatGrid> description;
    std::size_t window_bytes = 0;
};

class ScanRegionSource final : public GridRegionSource {
public:
    ScanRegionSource(OpenSlices open, const ConvertOptions& options) : open_(std::move(open)), options_(options) {
        options_.progress = nullptr;  // the survey reports progress, the bands do not
        survey(options.progress);
    }

    std::shared_ptr<const openvdb::FloatGrid> description() const override { return survey_.description; }
    std::vector<NodeWeight> nodes() const override { return survey_.nodes; }

    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox& box) const override {
        openvdb::FloatGrid::Ptr grid = survey_.description->deepCopy();
        const auto [first, last] = rows_of(box);
        if (first > last) return grid;
        const std::shared_ptr<const openvdb::FloatGrid> band = band_of_rows(first, last);
        TreeRegion region{detail::region_walk::to_bbox(box), &grid->tree(), {}};
        detail::region_walk::walk_region(band->tree(), region);
        for (const Leaf* leaf : region.leaves) grid->tree().addLeaf(new Leaf(*leaf));
        return grid;
    }

    std::uint64_t estimated_bytes(const IndexBox& box) const override {
        // The band (kept, the rows across the scan's whole x and y), the box's part of it, and
        // the converter's windows.
        return band_bytes(box) + grid_bytes(box) + survey_.window_bytes;
    }

    /// The band's leaves, times the share of the active voxels of the node layers the box
    /// meets that lie in nodes meeting the box (the survey counts leaves per row, active voxels
    /// per node); at least one node's worth of the band when the box holds active voxels.
    std::uint64_t grid_bytes(const IndexBox& box) const override {
        std::uint64_t inside = 0, across = 0;
        for (const NodeWeight& node : survey_.nodes) {
            if (node.origin[2] + kNodeVoxels <= box.min[2] || node.origin[2] >= box.max[2]) continue;
            across += node.active_voxels;
            const bool meets = node.origin[0] < box.max[0] && node.origin[0] + kNodeVoxels > box.min[0] && node.origin[1] < box.max[1] &&
                               node.origin[1] + kNodeVoxels > box.min[1];
            if (meets) inside += node.active_voxels;
        }
        if (across == 0) return 0;
        return std::uint64_t(double(band_bytes(box)) * double(inside) / double(across));
    }

private:
    /// The leaves of the rows the box meets, across the scan's whole x and y: the band a read
    /// of it makes.
    std::uint64_t band_bytes(const IndexBox& box) const {
        const auto [first, last] = rows_of(box);
        std::uint64_t leaves = 0;
        for (auto row = survey_.leaves.lower_bound(first); row != survey_.leaves.end() && row->first <= last; ++row) leaves += row->second;
        return leaves * (sizeof(Leaf) + Leaf::SIZE * sizeof(float));
    }

    /// The rows of the whole conversion that meet @a box in z: [first, last], empty when first > last.
    std::pair<int, int> rows_of(const IndexBox& box) const {
        const int first = std::max(first_row_, detail::floor_div(box.min[2], kLeafDim) * kLeafDim);
        const int last = std::min(last_row_, detail::floor_div(std::int64_t{box.max[2]} - 1, kLeafDim) * kLeafDim);
        return {first, last};
    }

    Conversion start_at(int row) const {
        Conversion conversion;
        conversion.reader = open_();
        conversion.converter = std::make_unique<Converter>(*conversion.reader, options_);
        conversion.next_row = row;
        return conversion;
    }

    void survey(const std::function<void(double)>& progress) {
        Conversion whole = start_at(0);
        first_row_ = whole.converter->first_row();
        last_row_ = whole.converter->last_row();
        std::map<std::tuple<int, int, int>, std::uint64_t> active;  // per node (z, y, x)
        const double slices = static_cast<double>(whole.reader->header().dims[2]);
        for (int z0 = first_row_; z0 <= last_row_; z0 += kLeafDim) {
            const ConvertedRow row = whole.converter->make_row(z0);
            for (const auto& leaf : row.leaves)
                active[{z0 & ~(kNodeVoxels - 1), leaf->origin().y() & ~(kNodeVoxels - 1), leaf->origin().x() & ~(kNodeVoxels - 1)}] +=
                    leaf->onVoxelCount();
            if (!row.leaves.empty()) survey_.leaves[z0] = row.leaves.size();
            if (progress) progress(std::clamp((z0 + kLeafDim) / slices, 0.0, 1.0));
        }
        for (const auto& [zyx, count] : active) survey_.nodes.push_back({{std::get<2>(zyx), std::get<1>(zyx), std::get<0>(zyx)}, count});
        survey_.values = whole.converter->values();
        std::vector<ConvertedRow> no_rows;
        survey_.description = whole.converter->assemble(no_rows, survey_.values);
        survey_.window_bytes = whole.converter->window_bytes();
    }

    /// The band of rows [first, last] (at least), made or kept.
    std::shared_ptr<const openvdb::FloatGrid> band_of_rows(int first, int last) const {
        std::lock_guard<std::mutex> lock(mutex_);
        if (band_ && band_first_ <= first && last <= band_last_) return band_;
        // The conversion runs TBB-parallel under the lock: isolated, so that this thread never
        // takes up another read() of the caller's while it waits (which would wait on the lock).
        tbb::this_task_arena::isolate([&] { make_band(first, last); });
        return band_;
    }

    void make_band(int first, int last) const {
        std::vector<ConvertedRow> rows;
        const bool follows = conversion_.converter && conversion_.next_row <= last &&
                             (conversion_.next_row <= first || (band_ && band_first_ <= first));
        if (!follows) conversion_ = start_at(first);
        if (conversion_.next_row < first) {
            // Ahead of the conversion: a fresh converter on the same reader skips the slices
            // between, unless the reader already holds some of the first row's window.
            if (conversion_.reader->next_slice() <= conversion_.converter->first_slice(first))
                conversion_.converter = std::make_unique<Converter>(*conversion_.reader, options_);
            else
                for (; conversion_.next_row < first; conversion_.next_row += kLeafDim) conversion_.converter->make_row(conversion_.next_row);
            conversion_.next_row = first;
        } else if (conversion_.next_row > first) {
            rows.push_back(rows_of_band(first, conversion_.next_row - kLeafDim));
        }
        for (; conversion_.next_row <= last; conversion_.next_row += kLeafDim)
            rows.push_back(conversion_.converter->make_row(conversion_.next_row));
        band_.reset();  // before the new band is assembled: one band at a time
        band_ = conversion_.converter->assemble(rows, survey_.values);
        band_first_ = first;
        band_last_ = last;
    }

    /// Copies of the leaves and tiles of the kept band in rows [first, last].
    ConvertedRow rows_of_band(int first, int last) const {
        ConvertedRow copy;
        const auto& tree = band_->tree();
        for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf)
            if (leaf->origin().z() >= first && leaf->origin().z() <= last) copy.leaves.push_back(std::make_unique<Leaf>(*leaf));
        auto tile = tree.cbeginValueAll();
        tile.setMinDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);  // the level-1 tiles the converter makes
        tile.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);
        for (; tile; ++tile)
            if (tile.getCoord().z() >= first && tile.getCoord().z() <= last && *tile != tree.background())
                copy.tiles.emplace_back(tile.getCoord(), *tile);
        return copy;
    }

    OpenSlices open_;
    ConvertOptions options_;
    Survey survey_;
    int first_row_ = 0, last_row_ = 0;

    mutable std::mutex mutex_;  // guards what follows
    mutable Conversion conversion_;
    mutable std::shared_ptr<const openvdb::FloatGrid> band_;
    mutable int band_first_ = 0, band_last_ = 0;
};

}  // namespace

std::unique_ptr<GridRegionSource> open_scan_regions(OpenSlices open, const ConvertOptions& options) {
    openvdb::initialize();
    const std::unique_ptr<SliceReader> first = open();
    detail::check_convert_options(first->header(), options);
    return std::make_unique<ScanRegionSource>(std::move(open), options);
}

}  // namespace vdbmesh
