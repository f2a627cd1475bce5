#pragma once
// Private: the streaming conversion of convert_to_grid() (convert.cpp), row by row, shared with
// the scan read by region (scan_regions.cpp), which makes only the rows a region needs.

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cstdint>
#include <future>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "vdbmesh/grid.h"
#include "vdbmesh/read.h"

namespace vdbmesh::detail {

using Leaf = openvdb::FloatTree::LeafNodeType;
constexpr int kLeafDim = static_cast<int>(Leaf::DIM);
/// Stand-in for samples outside the scan until the background is known: below any isovalue.
constexpr float kVirtual = std::numeric_limits<float>::lowest();

inline int floor_div(std::int64_t a, int b) { return static_cast<int>(a >= 0 ? a / b : -((-a + b - 1) / b)); }

/// Consecutive z-slices of one quantity over the padded frame; shift() drops the first ones.
template <typename T>
class SliceWindow {
public:
    SliceWindow(int count, std::size_t slice_size, T fill)
        : count_(count), size_(slice_size), data_(static_cast<std::size_t>(count) * slice_size, fill) {}
    std::size_t bytes() const { return data_.size() * sizeof(T); }
    T* slice(std::int64_t z) { return data_.data() + static_cast<std::size_t>(z - first_) * size_; }
    const T* slice(std::int64_t z) const { return data_.data() + static_cast<std::size_t>(z - first_) * size_; }
    std::int64_t first() const { return first_; }
    std::int64_t end() const { return first_ + count_; }
    /// Moves the window up to start at slice @a first, keeping the slices it already holds
    /// (their slots move down); returns the first slice it lacks, to be filled by the caller.
    std::int64_t move_to(std::int64_t first) {
        if (first_ < first && first < end()) {
            const std::int64_t lacking = end();
            const auto kept = static_cast<std::ptrdiff_t>(static_cast<std::size_t>(end() - first) * size_);
            std::copy(data_.end() - kept, data_.end(), data_.begin());
            first_ = first;
            return lacking;
        }
        first_ = first;
        return first;
    }

private:
    int count_;
    std::size_t size_;
    std::vector<T> data_;
    /// Far below every slice: the first move_to() keeps nothing.
    std::int64_t first_ = std::numeric_limits<std::int32_t>::min();
};

/// What one 8^3 block becomes.
struct BlockResult {
    std::unique_ptr<Leaf> leaf;
    bool tile = false;
    float tile_value = 0;
};

/// One row of blocks as the converter makes it: leaves in block order (y, then x) and the
/// inactive tiles of the blocks without an active voxel.
struct ConvertedRow {
    int z0 = 0;
    std::vector<std::unique_ptr<Leaf>> leaves;
    std::vector<std::pair<openvdb::Coord, float>> tiles;
};

/// The least and greatest sample read.
struct ScanValues {
    double min = std::numeric_limits<double>::max();
    double max = std::numeric_limits<double>::lowest();
};

/// Throws UsageError on bad options, FormatError on dims a grid cannot hold (convert_to_grid()'s checks).
void check_convert_options(const VolumeHeader& header, const ConvertOptions& options);

/// Whether voxel (x, y, z) lies in a scan of @a dims samples.
inline bool in_scan(const int (&dims)[3], int x, int y, int z) {
    return x >= 0 && y >= 0 && z >= 0 && x < dims[0] && y < dims[1] && z < dims[2];
}

/// Whether the whole 8^3 block at (x0, y0, z0) lies in a scan of @a dims samples.
inline bool block_in_scan(const int (&dims)[3], int x0, int y0, int z0) {
    return in_scan(dims, x0, y0, z0) && in_scan(dims, x0 + kLeafDim - 1, y0 + kLeafDim - 1, z0 + kLeafDim - 1);
}

/// Sets the voxels of @a row's leaves that lie outside a scan of @a dims samples to
/// @a background_value (what Converter::assemble() does to every row).
void fill_outside(ConvertedRow& row, const int (&dims)[3], float background_value);

/// A tree of @a rows (their leaves moved into it, @a rows emptied) over @a background_value.
openvdb::FloatTree::Ptr tree_of_rows(std::vector<ConvertedRow>& rows, float background_value);

/// The conversion of convert_to_grid(), row by row: a row is the 8-slice layer of blocks
/// (leaves) whose origin has z = z0. Each block depends only on the samples within band + 1
/// slices of its row, so a row is the same whether the conversion started at the scan's first
/// row or at any other; only the background needs the whole scan's value range.
class Converter {
public:
    /// @a options checked by check_convert_options(). @a source at its slice 0, or, when the
    /// first row made is not first_row(), at or before the first slice that row reads.
    Converter(SliceReader& source, const ConvertOptions& options);
    /// The rows of the whole conversion: z0 from first_row() to last_row(), step 8.
    int first_row() const { return floor_div(-pad_, kLeafDim) * kLeafDim; }
    int last_row() const { return floor_div(dims_[2] + band_, kLeafDim) * kLeafDim; }
    /// Makes row @a z0 (TBB-parallel); rows are made in increasing z0.
    ConvertedRow make_row(int z0);
    /// The range of the samples read so far: of the whole scan once every row was made.
    const ScanValues& values() const { return values_; }
    /// The bytes of the slice windows of a converter of a scan @a width x @a height samples across.
    static std::size_t window_bytes(std::int64_t width, std::int64_t height, int band);
    /// The grid of @a rows (their leaves moved into it): the background, and the metadata,
    /// from the whole scan's @a values.
    openvdb::FloatGrid::Ptr assemble(std::vector<ConvertedRow>& rows, const ScanValues& values) const;
    /// The background of a grid of this scan whose samples range over @a values.
    float background(const ScanValues& values) const;

private:
    std::int64_t frame_index(int x, int y) const { return (x + pad_) + width_ * static_cast<std::int64_t>(y + pad_); }
    bool in_scan(int x, int y, int z) const { return detail::in_scan(dims_, x, y, z); }
    bool block_in_scan(int x0, int y0, int z0) const { return detail::block_in_scan(dims_, x0, y0, z0); }

    void advance_samples(int z0);
    /// Slices [first, first + count) of the source into read_buffer_: the ones read ahead, if
    /// they are those, else read now (skipping to first).
    void take_slices(std::int64_t first, std::int64_t count);
    /// Starts reading slices [first, first + count), the source's next, on another thread: the
    /// source's reading and decoding then overlap this row's conversion.
    void read_ahead(std::int64_t first, std::int64_t count);
    /// Slice z of the padded frame from @a samples (the scan's slice z), or virtual outside
    /// the scan (@a samples null), with the value range of each 8 x 8 square of blocks in it.
    void fill_sample_slice(std::int64_t z, const float* samples);
    void compute_cell_slice(std::int64_t z);
    void compute_distance_slice(std::int64_t z);
    void summarise_distance_slice(std::int64_t z);
    /// Whether block (x0, y0, z0) may hold an active voxel (block_distances_ says where none can be).
    bool block_may_be_active(int x0, int y0, int z0) const;
    /// Which voxels (x0 .. x0 + 7, y, z) are active: an in-plane distance <= band - |dz| in slice z + dz.
    void active_row(int x0, int y, int z, bool* active) const;
    /// The least and greatest sample of the 8^3 block at (x0, y0, z0), which lies in the scan.
    std::pair<float, float> block_range(int x0, int y0, int z0) const;
    /// Index of the 8 x 8 square of the block at (x0, y0) in a slice of block_distances_, square_lo_, square_hi_.
    std::int64_t square_index(int x0, int y0) const {
        return static_cast<std::int64_t>(floor_div(y0, kLeafDim) - block_y_first_) * block_x_count_ +
               (floor_div(x0, kLeafDim) - block_x_first_);
    }
    BlockResult make_block(int x0, int y0, int z0) const;
    /// Skips the source's slices before @a slice (reading them): a first row after the scan's first.
    void skip_to(std::int64_t slice);

    SliceReader& source_;
    const VolumeHeader& header_;
    const ConvertOptions& options_;
    int band_;
    double iso_lo_, iso_hi_;
    float iso_lo_f_, iso_hi_f_;  ///< float_at_or_below() of the isovalues
    int dims_[3];  ///< the scan's samples in x, y, z
    int pad_;  ///< the frame holds voxels [-pad, dim + pad) in x and y: the band around the virtual ring
    std::int64_t width_, height_;
    int block_x_first_, block_x_count_, block_y_first_, block_y_count_;

    SliceWindow<float> samples_;           // [z0 - band - 1, z0 + 8 + band]
    SliceWindow<std::uint8_t> cells_;      // cell z spans samples z, z + 1: [z0 - band - 1, z0 + 7 + band]
    SliceWindow<std::uint8_t> distances_;  // voxels [z0 - band, z0 + 7 + band]
    /// Per slice of distances_ and 8 x 8 column of blocks: the least distance in the block's square.
    SliceWindow<std::uint8_t> block_distances_;
    /// Per slice of samples_ in the scan and 8 x 8 square of blocks: the least and greatest sample.
    SliceWindow<float> square_lo_, square_hi_;
    std::vector<float> read_buffer_;
    std::vector<float> ahead_buffer_;  ///< slices being read ahead: [ahead_first_, + ahead_count_)
    std::future<void> ahead_;          ///< declared after what it writes: waited for first on destruction
    std::int64_t ahead_first_ = 0, ahead_count_ = 0;

    std::vector<BlockResult> blocks_;  ///< of the row being made, y then x
    ScanValues values_;
};

}  // namespace vdbmesh::detail
