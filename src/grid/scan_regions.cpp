// A scan read by region, straight from its file: convert_to_grid()'s conversion made row by
// row (converter.h), a band of rows of one part of the slices at a time.
//
// Opening surveys the whole scan once: every row is made and dropped, keeping the sample range
// (the background and the metadata depend on it), each node's count of active voxels (nodes())
// and each row's count of leaves per node column (the estimates). That costs a conversion's time
// and its slice windows, never the grid.
// read(box) then needs the rows of leaves that meet the box in z, over the box's x-y rectangle
// widened by a halo (the part): the band. A voxel's state depends only on the cells within
// band of it in x and y (an in-plane distance saturating at band + 1), and a leaf's values are
// its own samples; at a part's edge that is not the scan's, the virtual ring marks the cells of
// the part's last column, band + 1 inside the edge. So with a halo of band + 1 the part's
// conversion gives every leaf meeting the box as the whole conversion does.
// The band last made is kept, so the bricks of one column, visited bottom to top, share one
// conversion of their part: the scan is read once per column, only the part's rows read and
// decoded. A band that follows the last (the same part, higher rows) goes on with the same
// converter (rows both share are copied from the last band); any other reopens the scan and
// skips to it. Each row is made from samples within band + 1 slices of it in z, so it equals
// the whole conversion's row there.

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

constexpr std::uint64_t kLeafBytes = sizeof(Leaf) + Leaf::SIZE * sizeof(float);

bool operator==(const SliceRectangle& a, const SliceRectangle& b) {
    return a.min_x == b.min_x && a.min_y == b.min_y && a.width == b.width && a.height == b.height;
}

/// A rectangle of a scan's slices seen as a scan of its own, its corner at (0, 0).
class SlicePartReader final : public SliceReader {
public:
    SlicePartReader(std::unique_ptr<SliceReader> scan, const SliceRectangle& part)
        : scan_(std::move(scan)), part_(part), header_(scan_->header()) {
        header_.dims[0] = part.width;
        header_.dims[1] = part.height;
    }
    const VolumeHeader& header() const override { return header_; }
    void read_slices(std::int64_t slices, float* out) override { scan_->read_slice_part(slices, part_, out); }
    std::int64_t next_slice() const override { return scan_->next_slice(); }

private:
    std::unique_ptr<SliceReader> scan_;
    SliceRectangle part_;
    VolumeHeader header_;
};

/// A part of the scan being converted from some row on: its reader and the converter reading
/// it, which makes leaves with the part's corner at (0, 0).
struct Conversion {
    std::unique_ptr<SliceReader> reader;
    std::unique_ptr<Converter> converter;
    SliceRectangle part;
    int next_row = 0;  ///< the row make_row() makes next
};

/// The leaves of the whole conversion per row and node column, summed over rectangles of node
/// columns in constant time (a table of sums per row).
class LeafCounts {
public:
    /// Columns of nodes from @a first_column on, @a columns_x x @a columns_y of them.
    LeafCounts(int first_column, int columns_x, int columns_y) : first_(first_column), nx_(columns_x), ny_(columns_y) {}

    void add_row(int z0, const std::vector<std::unique_ptr<Leaf>>& leaves) {
        if (leaves.empty()) return;
        std::vector<std::uint64_t> sums(std::size_t(nx_ + 1) * (ny_ + 1), 0);
        for (const auto& leaf : leaves) ++sums[index(column(leaf->origin().x()) + 1, column(leaf->origin().y()) + 1)];
        for (int y = 1; y <= ny_; ++y)
            for (int x = 1; x <= nx_; ++x) sums[index(x, y)] += sums[index(x - 1, y)] + sums[index(x, y - 1)] - sums[index(x - 1, y - 1)];
        rows_.emplace(z0, std::move(sums));
    }

    /// The leaves of rows [first, last] in the node columns meeting voxels [min_x, end_x) x [min_y, end_y).
    std::uint64_t leaves(int first, int last, std::int64_t min_x, std::int64_t end_x, std::int64_t min_y, std::int64_t end_y) const {
        const int x0 = std::max(column(min_x), 0), x1 = std::min(column(end_x - 1) + 1, nx_);
        const int y0 = std::max(column(min_y), 0), y1 = std::min(column(end_y - 1) + 1, ny_);
        if (x0 >= x1 || y0 >= y1) return 0;
        std::uint64_t count = 0;
        for (auto row = rows_.lower_bound(first); row != rows_.end() && row->first <= last; ++row) {
            const std::vector<std::uint64_t>& sums = row->second;
            count += sums[index(x1, y1)] - sums[index(x0, y1)] - sums[index(x1, y0)] + sums[index(x0, y0)];
        }
        return count;
    }

private:
    int column(std::int64_t voxel) const { return detail::floor_div(voxel, kNodeVoxels) - first_; }
    std::size_t index(int x, int y) const { return std::size_t(y) * (nx_ + 1) + x; }

    int first_, nx_, ny_;
    std::map<int, std::vector<std::uint64_t>> rows_;  ///< per row with leaves (z0): the sums
};

/// What the survey of the whole scan found.
struct Survey {
    detail::ScanValues values;
    float background = 0;
    std::vector<NodeWeight> nodes;  ///< z-major
    std::unique_ptr<LeafCounts> leaves;
    std::shared_ptr<const openvdb::FloatGrid> description;
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
        const SliceRectangle part = part_of(box);
        if (first > last || part.width <= 0 || part.height <= 0) return grid;
        const std::shared_ptr<const openvdb::FloatTree> band = band_of(first, last, part);
        TreeRegion region{detail::region_walk::to_bbox(box), &grid->tree(), {}};
        detail::region_walk::walk_region(*band, region);
        for (const Leaf* leaf : region.leaves) grid->tree().addLeaf(new Leaf(*leaf));
        return grid;
    }

    std::uint64_t estimated_bytes(const IndexBox& box) const override {
        // The band (kept), the box's part of it, and the part's converter windows with the
        // readers' buffers (a whole slice of floats at most).
        const SliceRectangle part = part_of(box);
        if (part.width <= 0 || part.height <= 0) return 0;
        const std::uint64_t windows = Converter::window_bytes(part.width, part.height, options_.band) +
                                      2 * std::uint64_t(whole_.width * whole_.height) * sizeof(float);
        const std::pair<int, int> rows = rows_of(box);
        return band_bytes(rows, part) + grid_bytes(rows, box) + windows;
    }

    std::uint64_t grid_bytes(const IndexBox& box) const override { return grid_bytes(rows_of(box), box); }

private:
    /// The leaves of @a rows (rows_of(box)) in the node columns the box meets.
    std::uint64_t grid_bytes(std::pair<int, int> rows, const IndexBox& box) const {
        return kLeafBytes * survey_.leaves->leaves(rows.first, rows.second, box.min[0], box.max[0], box.min[1], box.max[1]);
    }

    /// The leaves a read makes: @a rows over its @a part and the virtual ring the part's
    /// conversion adds round it (band + 1), counted by whole node columns.
    std::uint64_t band_bytes(std::pair<int, int> rows, const SliceRectangle& part) const {
        const auto [first, last] = rows;
        const int pad = options_.band + 1;
        return kLeafBytes * survey_.leaves->leaves(first, last, part.min_x - pad, part.min_x + part.width + pad, part.min_y - pad,
                                                   part.min_y + part.height + pad);
    }

    /// The rows of the whole conversion that meet @a box in z: [first, last], empty when first > last.
    std::pair<int, int> rows_of(const IndexBox& box) const {
        const int first = std::max(first_row_, detail::floor_div(box.min[2], kLeafDim) * kLeafDim);
        const int last = std::min(last_row_, detail::floor_div(std::int64_t{box.max[2]} - 1, kLeafDim) * kLeafDim);
        return {first, last};
    }

    /// The samples a read of @a box converts: the box's x-y rectangle widened by band + 1 (see
    /// the top of the file), in whole leaves so that the part's blocks are the scan's, within the
    /// scan's slices; empty when the box lies beyond every leaf the scan makes.
    SliceRectangle part_of(const IndexBox& box) const {
        const int halo = detail::floor_div(options_.band + 1 + kLeafDim - 1, kLeafDim) * kLeafDim;
        auto span = [&](std::int32_t min, std::int32_t max, std::int64_t min_scan, std::int64_t end_scan) {
            const std::int64_t first = std::max(min_scan, std::int64_t{detail::floor_div(min, kLeafDim)} * kLeafDim - halo);
            const std::int64_t end = std::min(end_scan, std::int64_t{detail::floor_div(std::int64_t{max} + kLeafDim - 1, kLeafDim)} * kLeafDim + halo);
            return std::make_pair(first, end - first);
        };
        const auto [min_x, width] = span(box.min[0], box.max[0], whole_.min_x, whole_.min_x + whole_.width);
        const auto [min_y, height] = span(box.min[1], box.max[1], whole_.min_y, whole_.min_y + whole_.height);
        return {min_x, min_y, width, height};
    }

    Conversion start_at(int row, const SliceRectangle& part) const {
        Conversion conversion;
        conversion.reader = std::make_unique<SlicePartReader>(open_(), part);
        conversion.converter = std::make_unique<Converter>(*conversion.reader, options_);
        conversion.part = part;
        conversion.next_row = row;
        return conversion;
    }

    void survey(const std::function<void(double)>& progress) {
        const std::unique_ptr<SliceReader> reader = open_();
        const VolumeHeader& header = reader->header();
        whole_ = {0, 0, header.dims[0], header.dims[1]};
        Converter whole(*reader, options_);
        first_row_ = whole.first_row();
        last_row_ = whole.last_row();
        // Node columns of every leaf the conversion can make: the scan and its virtual ring.
        const int pad = options_.band + 1;
        const int first_column = detail::floor_div(-pad, kNodeVoxels);
        auto columns = [&](std::int64_t dim) { return detail::floor_div(dim + pad, kNodeVoxels) - first_column + 1; };
        survey_.leaves = std::make_unique<LeafCounts>(first_column, columns(header.dims[0]), columns(header.dims[1]));
        std::map<std::tuple<int, int, int>, std::uint64_t> active;  // per node (z, y, x)
        const double slices = static_cast<double>(header.dims[2]);
        for (int z0 = first_row_; z0 <= last_row_; z0 += kLeafDim) {
            const ConvertedRow row = whole.make_row(z0);
            for (const auto& leaf : row.leaves)
                active[{z0 & ~(kNodeVoxels - 1), leaf->origin().y() & ~(kNodeVoxels - 1), leaf->origin().x() & ~(kNodeVoxels - 1)}] +=
                    leaf->onVoxelCount();
            survey_.leaves->add_row(z0, row.leaves);
            if (progress) progress(std::clamp((z0 + kLeafDim) / slices, 0.0, 1.0));
        }
        for (const auto& [zyx, count] : active) survey_.nodes.push_back({{std::get<2>(zyx), std::get<1>(zyx), std::get<0>(zyx)}, count});
        survey_.values = whole.values();
        survey_.background = whole.background(survey_.values);
        std::vector<ConvertedRow> no_rows;
        survey_.description = whole.assemble(no_rows, survey_.values);
    }

    /// The band of rows [first, last] (at least) of @a part, made or kept.
    std::shared_ptr<const openvdb::FloatTree> band_of(int first, int last, const SliceRectangle& part) const {
        std::lock_guard<std::mutex> lock(mutex_);
        if (band_ && conversion_.part == part && band_first_ <= first && last <= band_last_) return band_;
        // The conversion runs TBB-parallel under the lock: isolated, so that this thread never
        // takes up another read() of the caller's while it waits (which would wait on the lock).
        tbb::this_task_arena::isolate([&] { make_band(first, last, part); });
        return band_;
    }

    void make_band(int first, int last, const SliceRectangle& part) const {
        std::vector<ConvertedRow> rows;
        const bool follows = conversion_.converter && conversion_.part == part && conversion_.next_row <= last &&
                             (conversion_.next_row <= first || (band_ && band_first_ <= first));
        if (!follows) conversion_ = start_at(first, part);
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
        for (; conversion_.next_row <= last; conversion_.next_row += kLeafDim) rows.push_back(made_row(conversion_.next_row));
        band_.reset();  // before the new band is built: one band at a time
        band_ = detail::tree_of_rows(rows, survey_.background);
        band_first_ = first;
        band_last_ = last;
    }

    /// Row @a z0 of the conversion's part, in the scan's coordinates.
    ConvertedRow made_row(int z0) const {
        ConvertedRow row = conversion_.converter->make_row(z0);
        conversion_.converter->fill_outside(row, survey_.background);
        const openvdb::Coord corner(static_cast<int>(conversion_.part.min_x), static_cast<int>(conversion_.part.min_y), 0);
        for (auto& leaf : row.leaves) leaf->setOrigin(leaf->origin() + corner);
        for (auto& tile : row.tiles) tile.first += corner;
        return row;
    }

    /// Copies of the leaves and tiles of the kept band in rows [first, last].
    ConvertedRow rows_of_band(int first, int last) const {
        ConvertedRow copy;
        const openvdb::FloatTree& tree = *band_;
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
    SliceRectangle whole_;  ///< the scan's slices
    int first_row_ = 0, last_row_ = 0;

    mutable std::mutex mutex_;  // guards what follows
    mutable Conversion conversion_;
    mutable std::shared_ptr<const openvdb::FloatTree> band_;
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
