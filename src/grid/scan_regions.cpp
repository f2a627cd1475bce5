// A scan read by region, straight from its file: convert_to_grid()'s conversion made row by
// row (converter.h) once, by the survey, which keeps every row it makes (kept_rows.h).
//
// Opening surveys the whole scan: every row is made, written to a temporary file grouped by node
// column, and dropped, keeping in memory the sample range (the background and the metadata
// depend on it), each node's count of active voxels (nodes()) and each row's count of leaves per
// node column (the estimates). That costs a conversion's time and slice windows, and a temporary
// file of the active leaves (2 bytes a value for a scan of 16-bit integers), never the grid.
// read(box) then reads back the rows of leaves that meet the box in z, in the node columns that
// meet it in x and y, and keeps what meets the box. The survey's rows are the whole
// conversion's, so the leaves are exactly convert_to_grid()'s once the voxels outside the scan
// are set to the background (known only at the survey's end). The scan file is read once,
// whatever the order of the reads: before, each column of bricks converted its part of the
// scan again (a pass over the file per column; session 19, k = 6: three passes over 41 GB).

#include <map>
#include <stdexcept>
#include <tuple>

#include "converter.h"
#include "kept_rows.h"
#include "leaf_masks.h"
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

constexpr std::uint64_t kLeafBytes = sizeof(Leaf) + Leaf::SIZE * sizeof(float);

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
    ScanRegionSource(const OpenSlices& open, const ConvertOptions& options, ScanRegionReads reads) { survey(open, options, reads); }

    std::shared_ptr<const openvdb::FloatGrid> description() const override { return survey_.description; }
    std::vector<NodeWeight> nodes() const override { return survey_.nodes; }

    std::shared_ptr<openvdb::FloatGrid> read(const IndexBox& box) const override {
        openvdb::FloatGrid::Ptr grid = survey_.description->deepCopy();
        const auto [first, last] = rows_of(box);
        if (first > last) return grid;
        const openvdb::CoordBBox bbox = detail::region_walk::to_bbox(box);
        openvdb::FloatTree& tree = grid->tree();
        std::vector<ConvertedRow> rows = kept_rows(first, last, box);
        for (ConvertedRow& row : rows) {
            detail::fill_outside(row, dims_, survey_.background);
            for (auto& leaf : row.leaves)
                if (leaf->getNodeBoundingBox().hasOverlap(bbox)) tree.addLeaf(leaf.release());
            for (const auto& [origin, value] : row.tiles)  // as the walk of region_walk.h copies a tile
                if (value != survey_.background && openvdb::CoordBBox::createCube(origin, kLeafDim).hasOverlap(bbox))
                    tree.addTile(1, origin, value, false);
        }
        return grid;
    }

    /// The leaves read back (those of the box's node columns over its rows) and the buffer of
    /// one node row's stretch of the file.
    std::uint64_t estimated_bytes(const IndexBox& box) const override {
        return grid_bytes(rows_of(box), box) + (kept_ ? kept_->buffer_bytes() : 0);
    }

    std::uint64_t opening_bytes() const override { return survey_windows_; }

    /// Row by row from the kept rows: one row's leaves held at a time, never the region.
    std::vector<LeafMask> active_leaves(const IndexBox& box) const override {
        std::vector<LeafMask> masks;
        const auto [first, last] = rows_of(box);
        for (int z0 = first; z0 <= last; z0 += kLeafDim) {
            std::vector<ConvertedRow> row = kept_rows(z0, z0, box);
            const std::vector<LeafMask> of_row = detail::leaf_masks(*detail::tree_of_rows(row, survey_.background), box);
            masks.insert(masks.end(), of_row.begin(), of_row.end());
        }
        return masks;
    }

    std::uint64_t grid_bytes(const IndexBox& box) const override { return grid_bytes(rows_of(box), box); }

private:
    /// The kept rows with z0 in [first, last], in the node columns that meet @a box.
    std::vector<ConvertedRow> kept_rows(int first, int last, const IndexBox& box) const {
        if (!kept_) throw std::logic_error("scan_regions: a read of a scan surveyed without keeping its rows");
        return kept_->read(first, last, kept_->column(box.min[0]), kept_->column(box.max[0] - 1) + 1, kept_->column(box.min[1]),
                           kept_->column(box.max[1] - 1) + 1);
    }

    /// The leaves of @a rows (rows_of(box)) in the node columns the box meets.
    std::uint64_t grid_bytes(std::pair<int, int> rows, const IndexBox& box) const {
        return kLeafBytes * survey_.leaves->leaves(rows.first, rows.second, box.min[0], box.max[0], box.min[1], box.max[1]);
    }

    /// The rows of the whole conversion that meet @a box in z: [first, last], empty when first > last.
    std::pair<int, int> rows_of(const IndexBox& box) const {
        const int first = std::max(first_row_, detail::floor_div(box.min[2], kLeafDim) * kLeafDim);
        const int last = std::min(last_row_, detail::floor_div(std::int64_t{box.max[2]} - 1, kLeafDim) * kLeafDim);
        return {first, last};
    }

    void survey(const OpenSlices& open, const ConvertOptions& options, ScanRegionReads reads) {
        ConvertOptions converting = options;
        converting.progress = nullptr;  // the survey reports its own
        const std::unique_ptr<SliceReader> reader = open();
        const VolumeHeader& header = reader->header();
        for (int axis = 0; axis < 3; ++axis) dims_[axis] = static_cast<int>(header.dims[axis]);
        Converter whole(*reader, converting);
        survey_windows_ = Converter::window_bytes(header.dims[0], header.dims[1], options.band);
        first_row_ = whole.first_row();
        last_row_ = whole.last_row();
        // Node columns of every leaf the conversion can make: the scan and its virtual ring.
        const int pad = options.band + 1;
        const int first_column = detail::floor_div(-pad, kNodeVoxels);
        auto columns = [&](std::int64_t dim) { return detail::floor_div(dim + pad, kNodeVoxels) - first_column + 1; };
        survey_.leaves = std::make_unique<LeafCounts>(first_column, columns(header.dims[0]), columns(header.dims[1]));
        if (reads == ScanRegionReads::by_region)
            kept_ = std::make_unique<detail::KeptRows>(first_column, columns(header.dims[0]), columns(header.dims[1]));
        std::map<std::tuple<int, int, int>, std::uint64_t> active;  // per node (z, y, x)
        const double slices = static_cast<double>(header.dims[2]);
        for (int z0 = first_row_; z0 <= last_row_; z0 += kLeafDim) {
            const ConvertedRow row = whole.make_row(z0);
            for (const auto& leaf : row.leaves)
                active[{z0 & ~(kNodeVoxels - 1), leaf->origin().y() & ~(kNodeVoxels - 1), leaf->origin().x() & ~(kNodeVoxels - 1)}] +=
                    leaf->onVoxelCount();
            survey_.leaves->add_row(z0, row.leaves);
            if (kept_) kept_->add(row);
            if (options.progress) options.progress(std::clamp((z0 + kLeafDim) / slices, 0.0, 1.0));
        }
        for (const auto& [zyx, count] : active) survey_.nodes.push_back({{std::get<2>(zyx), std::get<1>(zyx), std::get<0>(zyx)}, count});
        survey_.values = whole.values();
        survey_.background = whole.background(survey_.values);
        std::vector<ConvertedRow> no_rows;
        survey_.description = whole.assemble(no_rows, survey_.values);
    }

    Survey survey_;
    std::unique_ptr<detail::KeptRows> kept_;  ///< null when surveyed for the estimates only
    int dims_[3] = {0, 0, 0};
    int first_row_ = 0, last_row_ = 0;
    std::uint64_t survey_windows_ = 0;
};

}  // namespace

std::unique_ptr<GridRegionSource> open_scan_regions(OpenSlices open, const ConvertOptions& options, ScanRegionReads reads) {
    openvdb::initialize();
    {
        const std::unique_ptr<SliceReader> first = open();
        detail::check_convert_options(first->header(), options);
    }
    return std::make_unique<ScanRegionSource>(open, options, reads);
}

}  // namespace vdbmesh
