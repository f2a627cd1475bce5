// Streaming conversion of a scan into a sparse FloatGrid (DESIGN.md section 3).
//
// The scan is read one 8-slice block row at a time (a leaf is 8^3), with a window of
// band + 1 extra slices on each side. For each row:
//   1. cells straddling the isovalue are flagged (a cell's 8 samples have min <= iso < max
//      for some iso of the requested range; samples outside the scan are "virtual", below
//      every isovalue, so the surface closes where the object touches the scan's border);
//   2. the corners of those cells are marked, and an in-plane city-block distance to the
//      nearest mark is computed per slice (separable: row passes, then column passes);
//   3. a voxel is active when a mark lies within L1 distance `band` in 3D, i.e. when some
//      slice z + dz has an in-plane distance <= band - |dz| (a face-connected dilation,
//      like OpenVDB's default NN_FACE, applied `band` times);
//   4. every 8^3 block of the row becomes, in parallel, a leaf (if it has an active voxel),
//      an inactive tile, or nothing (background); results are added in a fixed order, so
//      the grid is the same whatever the thread count.
// Inactive voxels keep their sample, which is on the right side of the isovalue by
// construction. A block without active voxels has all its samples on one side of every
// isovalue of the range (its cells do not straddle), so its minimum sample is a correct tile
// value; blocks wholly at or below the range's low end, or reaching outside the scan,
// become background.
// The rows are made one at a time by detail::Converter (converter.h): convert_to_grid() makes
// them all; a scan read by region (scan_regions.cpp) makes those its bands need.

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <memory>
#include <vector>

#include "converter.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"

namespace vdbmesh::detail {

namespace {

constexpr int kMaxBand = 32;

/// The largest float <= @a value: for a float f, f <= value iff f <= float_at_or_below(value),
/// and f > value iff f > float_at_or_below(value), so the tests run on floats.
float float_at_or_below(double value) {
    float f = static_cast<float>(value);
    if (static_cast<double>(f) > value) f = std::nextafter(f, std::numeric_limits<float>::lowest());
    return f;
}


}  // namespace

void check_convert_options(const VolumeHeader& header, const ConvertOptions& options) {
    if (options.band < 1 || options.band > kMaxBand)
        throw UsageError("band: expected 1 to " + std::to_string(kMaxBand) + " voxels, got " +
                         std::to_string(options.band));
    const double lo = options.iso_range ? options.iso_range->first : options.iso;
    const double hi = options.iso_range ? options.iso_range->second : options.iso;
    const double limit = 0.5 * std::numeric_limits<float>::max();
    if (!(lo >= -limit && hi <= limit && lo <= hi))
        throw UsageError(std::string(options.iso_range ? "--iso-range: expected A <= B" : "--iso: expected a value") +
                         " within half the float range (|iso| <= 1.7e38), got " + std::to_string(lo) +
                         (options.iso_range ? ", " + std::to_string(hi) : std::string()));
    // Voxel coordinates are 32-bit in OpenVDB; keep room for the band and a leaf.
    const std::int64_t max_dim = std::numeric_limits<std::int32_t>::max() - 2 * (kMaxBand + kLeafDim);
    for (int axis = 0; axis < 3; ++axis)
        if (header.dims[axis] < 1 || header.dims[axis] > max_dim)
            throw FormatError(header.path.string(), "dims", "1 to " + std::to_string(max_dim) + " samples per axis",
                              std::to_string(header.dims[axis]));
}

namespace {

/// Min and max of each column i < n over the 2 x 2 samples of rows a and b of slices 0 and 1.
void column_ranges(const float* __restrict a0, const float* __restrict b0, const float* __restrict a1,
                   const float* __restrict b1, float* __restrict lo, float* __restrict hi, std::int64_t n) {
    // Samples copied to locals: std::min on array elements selects addresses, which does not vectorise.
    for (std::int64_t i = 0; i < n; ++i) {
        const float a = a0[i], b = b0[i], c = a1[i], d = b1[i];
        lo[i] = std::min(std::min(a, b), std::min(c, d));
        hi[i] = std::max(std::max(a, b), std::max(c, d));
    }
}

/// out[i] for i < n: whether cell i (columns i and i + 1) straddles an isovalue of
/// [iso_lo, iso_hi] (its samples' min <= iso_hi and max > iso_lo, and min < max).
void mark_straddling(const float* __restrict lo, const float* __restrict hi, float iso_lo, float iso_hi,
                     std::uint8_t* __restrict out, std::int64_t n) {
    for (std::int64_t i = 0; i < n; ++i) {
        const float lo0 = lo[i], lo1 = lo[i + 1], hi0 = hi[i], hi1 = hi[i + 1];
        const float cell_min = std::min(lo0, lo1), cell_max = std::max(hi0, hi1);
        out[i] = (cell_min < cell_max) & (cell_min <= iso_hi) & (cell_max > iso_lo);
    }
}

/// out[i] = a[i] | b[i] for i < n.
void or_rows(std::uint8_t* __restrict out, const std::uint8_t* __restrict a, const std::uint8_t* __restrict b,
             std::int64_t n) {
    for (std::int64_t i = 0; i < n; ++i) out[i] = a[i] | b[i];
}

/// d[i] = 0 where marked[i], else far, for i < n; returns whether any is marked.
bool place_marks(std::uint8_t* __restrict d, const std::uint8_t* __restrict marked, std::uint8_t far, std::int64_t n) {
    std::uint8_t any = 0;
    for (std::int64_t i = 0; i < n; ++i) {
        d[i] = marked[i] ? 0 : far;
        any |= marked[i];
    }
    return any != 0;
}

/// d[i] = min(d[i], step) where marked[i + offset] (within 0 .. n - 1), for i < n.
void mark_distance(std::uint8_t* __restrict d, const std::uint8_t* __restrict marked, std::int64_t offset,
                   std::uint8_t step, std::uint8_t far, std::int64_t n) {
    const std::int64_t begin = std::max<std::int64_t>(0, -offset), end = std::min(n, n - offset);
    for (std::int64_t i = begin; i < end; ++i) d[i] = std::min(d[i], marked[i + offset] ? step : far);
}

/// out[i] = min(out[i], from[i] + 1) for i < n: one step of a distance transform across rows
/// (two rows of a slice, which never overlap).
void relax_row(std::uint8_t* __restrict out, const std::uint8_t* __restrict from, std::int64_t n) {
    for (std::int64_t i = 0; i < n; ++i) out[i] = std::min(out[i], static_cast<std::uint8_t>(from[i] + 1));
}

}  // namespace

Converter::Converter(SliceReader& source, const ConvertOptions& options)
    : source_(source),
      header_(source.header()),
      options_(options),
      band_(options.band),
      iso_lo_(options.iso_range ? options.iso_range->first : options.iso),
      iso_hi_(options.iso_range ? options.iso_range->second : options.iso),
      iso_lo_f_(float_at_or_below(iso_lo_)),
      iso_hi_f_(float_at_or_below(iso_hi_)),
      dims_{static_cast<int>(header_.dims[0]), static_cast<int>(header_.dims[1]), static_cast<int>(header_.dims[2])},
      pad_(band_ + 1),
      width_(dims_[0] + 2 * pad_),
      height_(dims_[1] + 2 * pad_),
      block_x_first_(floor_div(-pad_, kLeafDim)),
      block_x_count_(floor_div(dims_[0] + band_, kLeafDim) - block_x_first_ + 1),
      block_y_first_(floor_div(-pad_, kLeafDim)),
      block_y_count_(floor_div(dims_[1] + band_, kLeafDim) - block_y_first_ + 1),
      samples_(kLeafDim + 2 * pad_, static_cast<std::size_t>(width_ * height_), kVirtual),
      cells_(kLeafDim + 2 * band_ + 1, static_cast<std::size_t>(width_ * height_), 0),
      distances_(kLeafDim + 2 * band_, static_cast<std::size_t>(width_ * height_), 0),
      block_distances_(kLeafDim + 2 * band_, static_cast<std::size_t>(block_y_count_) * block_x_count_, 0),
      square_lo_(kLeafDim + 2 * pad_, static_cast<std::size_t>(block_y_count_) * block_x_count_, 0),
      square_hi_(kLeafDim + 2 * pad_, static_cast<std::size_t>(block_y_count_) * block_x_count_, 0),
      blocks_(static_cast<std::size_t>(block_x_count_) * block_y_count_) {}

std::size_t Converter::window_bytes(std::int64_t width, std::int64_t height, int band) {
    // What the constructor allocates (the windows), and the read buffer of advance_samples().
    const std::int64_t pad = band + 1;
    const auto frame = static_cast<std::size_t>((width + 2 * pad) * (height + 2 * pad));
    const auto blocks = static_cast<std::size_t>((floor_div(width + band, kLeafDim) - floor_div(-pad, kLeafDim) + 1) *
                                                 (floor_div(height + band, kLeafDim) - floor_div(-pad, kLeafDim) + 1));
    const std::size_t sample_slices = kLeafDim + 2 * pad, distance_slices = kLeafDim + 2 * band;
    return sample_slices * frame * sizeof(float) + (distance_slices + 1) * frame + distance_slices * frame + distance_slices * blocks +
           2 * sample_slices * blocks * sizeof(float) + sample_slices * static_cast<std::size_t>(width * height) * sizeof(float);
}

void Converter::skip_to(std::int64_t slice) {
    if (source_.next_slice() > slice) throw Error("internal: the conversion's source is past slice " + std::to_string(slice));
    const auto slice_voxels = static_cast<std::size_t>(header_.slice_voxels());
    while (source_.next_slice() < slice) {
        const std::int64_t count = std::min<std::int64_t>(slice - source_.next_slice(), kLeafDim);
        read_buffer_.resize(slice_voxels * static_cast<std::size_t>(count));
        source_.read_slices(count, read_buffer_.data());
    }
}

void Converter::take_slices(std::int64_t first, std::int64_t count) {
    if (ahead_.valid()) {
        ahead_.get();  // rethrows the read's error
        if (ahead_first_ == first && ahead_count_ == count) {
            std::swap(read_buffer_, ahead_buffer_);
            return;
        }
    }
    skip_to(first);
    read_buffer_.resize(static_cast<std::size_t>(header_.slice_voxels()) * static_cast<std::size_t>(count));
    source_.read_slices(count, read_buffer_.data());
}

void Converter::read_ahead(std::int64_t first, std::int64_t count) {
    // A second thread only where more than one may run: with --threads 1, one.
    if (count <= 0 || tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism) < 2) return;
    ahead_first_ = first;
    ahead_count_ = count;
    ahead_buffer_.resize(static_cast<std::size_t>(header_.slice_voxels()) * static_cast<std::size_t>(count));
    ahead_ = std::async(std::launch::async, [this, count] { source_.read_slices(count, ahead_buffer_.data()); });
}

void Converter::fill_sample_slice(std::int64_t z, const float* samples) {
    float* out = samples_.slice(z);
    if (!samples) {
        std::fill(out, out + width_ * height_, kVirtual);
        return;
    }
    float* lows = square_lo_.slice(z);
    float* highs = square_hi_.slice(z);
    std::fill(lows, lows + static_cast<std::int64_t>(block_y_count_) * block_x_count_, std::numeric_limits<float>::max());
    std::fill(highs, highs + static_cast<std::int64_t>(block_y_count_) * block_x_count_, std::numeric_limits<float>::lowest());
    for (int y = 0; y < dims_[1]; ++y) {
        const float* row = samples + static_cast<std::size_t>(y) * dims_[0];
        std::copy_n(row, dims_[0], out + frame_index(0, y));
        // The scan starts at a block boundary: its x runs in blocks of 8 from x = 0.
        const std::int64_t squares = square_index(0, y);
        for (int x0 = 0; x0 < dims_[0]; x0 += kLeafDim) {
            float lo = lows[squares + x0 / kLeafDim], hi = highs[squares + x0 / kLeafDim];
            for (int x = x0; x < std::min(x0 + kLeafDim, dims_[0]); ++x) {
                const float value = row[x];
                lo = std::min(lo, value);
                hi = std::max(hi, value);
            }
            lows[squares + x0 / kLeafDim] = lo;
            highs[squares + x0 / kLeafDim] = hi;
        }
    }
}

void Converter::advance_samples(int z0) {
    // The slices the window lacks, read in one go and framed in parallel.
    const std::int64_t first = samples_.move_to(z0 - band_ - 1), end = samples_.end();
    square_lo_.move_to(z0 - band_ - 1);
    square_hi_.move_to(z0 - band_ - 1);
    const std::int64_t scan_first = std::clamp<std::int64_t>(first, 0, dims_[2]);
    const std::int64_t scan_end = std::clamp<std::int64_t>(end, 0, dims_[2]);
    const auto slice_voxels = static_cast<std::size_t>(header_.slice_voxels());
    if (scan_end > scan_first) {
        take_slices(scan_first, scan_end - scan_first);
        read_ahead(scan_end, std::min<std::int64_t>(kLeafDim, dims_[2] - scan_end));  // the next row's
    }
    tbb::parallel_for(first, end, [&](std::int64_t z) {
        const bool in_scan = z >= scan_first && z < scan_end;
        fill_sample_slice(z, in_scan ? read_buffer_.data() + static_cast<std::size_t>(z - scan_first) * slice_voxels : nullptr);
    });
    const std::size_t squares = static_cast<std::size_t>(block_y_count_) * block_x_count_;
    for (std::int64_t z = scan_first; z < scan_end; ++z) {
        values_.min = std::min<double>(values_.min, *std::min_element(square_lo_.slice(z), square_lo_.slice(z) + squares));
        values_.max = std::max<double>(values_.max, *std::max_element(square_hi_.slice(z), square_hi_.slice(z) + squares));
    }
}

void Converter::compute_cell_slice(std::int64_t z) {
    const float* s0 = samples_.slice(z);
    const float* s1 = samples_.slice(z + 1);
    std::uint8_t* out = cells_.slice(z);
    const std::int64_t width = width_, height = height_;
    std::vector<float> column_min(static_cast<std::size_t>(width)), column_max(static_cast<std::size_t>(width));
    for (std::int64_t row = 0; row + 1 < height; ++row) {
        const std::int64_t r0 = row * width, r1 = r0 + width;
        column_ranges(s0 + r0, s0 + r1, s1 + r0, s1 + r1, column_min.data(), column_max.data(), width);
        mark_straddling(column_min.data(), column_max.data(), iso_lo_f_, iso_hi_f_, out + r0, width - 1);
        out[r0 + width - 1] = 0;
    }
    std::fill(out + (height - 1) * width, out + height * width, 0);
}

void Converter::compute_distance_slice(std::int64_t z) {
    const std::uint8_t* below = cells_.slice(z - 1);
    const std::uint8_t* above = cells_.slice(z);
    std::uint8_t* d = distances_.slice(z);
    // Distances only matter up to the band: they saturate at band + 1 (so d + band fits a byte).
    const auto far = static_cast<std::uint8_t>(band_ + 1);
    // A voxel is a corner of the cells (x-1..x, y-1..y, z-1..z); mark it when one straddles.
    // The frame's first row and column lie beyond the virtual ring: no straddling cell there.
    // City-block distance is separable: exact 1D distances along each row with a mark (the
    // nearest mark within the band on either side), then a recurrence along the columns (one
    // pass each way). Every loop runs over whole rows, so that the compiler vectorises it.
    const std::int64_t w = width_, height = height_;
    const int band = band_;
    std::vector<std::uint8_t> rows(4 * static_cast<std::size_t>(w));
    std::uint8_t* previous = rows.data();  // cells of the previous frame row straddling in slice z - 1 or z
    std::uint8_t* current = previous + w;  // the same for this row
    std::uint8_t* columns = current + w;   // either of them
    std::uint8_t* marked = columns + w;    // marks of this row's voxels
    or_rows(previous, below, above, w);
    std::fill(d, d + w, far);
    // Rows further than the band from every row with a mark stay far: the column passes skip them.
    std::vector<std::uint8_t> near_mark(static_cast<std::size_t>(height), 0);
    for (std::int64_t row = 1; row < height; ++row) {
        std::uint8_t* r = d + row * w;
        or_rows(current, below + row * w, above + row * w, w);
        or_rows(columns, current, previous, w);
        or_rows(marked + 1, columns, columns + 1, w - 1);
        std::swap(previous, current);
        marked[0] = 0;
        if (!place_marks(r, marked, far, w)) continue;
        std::fill(near_mark.begin() + std::max<std::int64_t>(row - band, 0),
                  near_mark.begin() + std::min<std::int64_t>(row + band + 1, height), 1);
        for (int k = 1; k <= band; ++k) {
            mark_distance(r, marked, -k, static_cast<std::uint8_t>(k), far, w);
            mark_distance(r, marked, k, static_cast<std::uint8_t>(k), far, w);
        }
    }
    for (std::int64_t row = 1; row < height; ++row)
        if (near_mark[static_cast<std::size_t>(row)]) relax_row(d + row * w, d + (row - 1) * w, w);
    for (std::int64_t row = height - 1; row-- > 0;)
        if (near_mark[static_cast<std::size_t>(row)]) relax_row(d + row * w, d + (row + 1) * w, w);
}

void Converter::summarise_distance_slice(std::int64_t z) {
    const std::uint8_t* d = distances_.slice(z);
    std::uint8_t* summary = block_distances_.slice(z);
    std::fill(summary, summary + static_cast<std::int64_t>(block_y_count_) * block_x_count_, std::uint8_t(255));
    for (std::int64_t row = 0; row < height_; ++row) {
        const std::uint8_t* r = d + row * width_;
        std::uint8_t* blocks = summary + static_cast<std::int64_t>(floor_div(row - pad_, kLeafDim) - block_y_first_) * block_x_count_;
        for (int b = 0; b < block_x_count_; ++b) {
            // The block's voxels x0 .. x0 + 7 within the frame (voxels -pad .. dim + pad - 1).
            const int x0 = (block_x_first_ + b) * kLeafDim;
            const std::int64_t begin = std::max(x0, -pad_) + pad_, end = std::min(x0 + kLeafDim, dims_[0] + pad_) + pad_;
            for (std::int64_t x = begin; x < end; ++x) blocks[b] = std::min(blocks[b], r[x]);
        }
    }
}

bool Converter::block_may_be_active(int x0, int y0, int z0) const {
    const std::int64_t block = square_index(x0, y0);
    for (int z = z0; z < z0 + kLeafDim; ++z)
        for (int dz = -band_; dz <= band_; ++dz)
            if (block_distances_.slice(z + dz)[block] <= band_ - std::abs(dz)) return true;
    return false;
}

void Converter::active_row(int x0, int y, int z, bool* active) const {
    std::fill(active, active + kLeafDim, false);
    if (y < -pad_ || y >= dims_[1] + pad_) return;
    const int begin = std::max(x0, -pad_) - x0, end = std::min(x0 + kLeafDim, dims_[0] + pad_) - x0;
    if (begin >= end) return;
    const std::int64_t f = frame_index(x0 + begin, y);
    for (int dz = -band_; dz <= band_; ++dz) {
        const std::uint8_t* d = distances_.slice(z + dz) + f;
        const int limit = band_ - std::abs(dz);
        for (int i = begin; i < end; ++i) active[i] |= d[i - begin] <= limit;
    }
}

std::pair<float, float> Converter::block_range(int x0, int y0, int z0) const {
    const std::int64_t square = square_index(x0, y0);
    float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
    for (int z = z0; z < z0 + kLeafDim; ++z) {
        lo = std::min(lo, square_lo_.slice(z)[square]);
        hi = std::max(hi, square_hi_.slice(z)[square]);
    }
    return {lo, hi};
}

BlockResult Converter::make_block(int x0, int y0, int z0) const {
    BlockResult result;
    Leaf::NodeMaskType active;
    bool row[kLeafDim];
    if (block_may_be_active(x0, y0, z0))
        for (int z = z0; z < z0 + kLeafDim; ++z)
            for (int y = y0; y < y0 + kLeafDim; ++y) {
                active_row(x0, y, z, row);
                for (int i = 0; i < kLeafDim; ++i)
                    if (row[i]) active.setOn(Leaf::coordToOffset(openvdb::Coord(x0 + i, y, z)));
            }

    if (active.isOff()) {
        // No active voxel: every sample of the block is on one side of every isovalue. A block
        // reaching outside the scan shares a cell with the virtual ring, so it is outside.
        if (!block_in_scan(x0, y0, z0)) return result;
        const auto [lo, hi] = block_range(x0, y0, z0);
        if (hi > iso_lo_f_) {  // inside for some isovalue: keep the block's minimum
            result.tile = true;
            result.tile_value = lo;
        }
        return result;
    }

    result.leaf = std::make_unique<Leaf>(openvdb::Coord(x0, y0, z0), kVirtual, false);
    float* values = result.leaf->buffer().data();
    for (int z = std::max(z0, 0); z < std::min(z0 + kLeafDim, dims_[2]); ++z)
        for (int y = std::max(y0, 0); y < std::min(y0 + kLeafDim, dims_[1]); ++y) {
            const float* row = samples_.slice(z) + frame_index(0, y);
            for (int x = std::max(x0, 0); x < std::min(x0 + kLeafDim, dims_[0]); ++x)
                values[Leaf::coordToOffset(openvdb::Coord(x, y, z))] = row[x];
        }
    result.leaf->setValueMask(active);
    return result;
}

float Converter::background(const ScanValues& values) const {
    // Below every isovalue and every sample by 1% of the value range (outside reads as air,
    // and no sample ties with it), clamped to the float range.
    const double floor = std::min(values.min, iso_lo_);
    const double range = values.max - values.min;
    const double margin = std::max(0.01 * range, 1e-6 * std::max(1.0, std::abs(floor)));
    const double lowest = std::numeric_limits<float>::lowest();
    float value = static_cast<float>(std::max(floor - margin, lowest));
    while (static_cast<double>(value) >= floor && value > std::numeric_limits<float>::lowest())
        value = std::nextafter(value, std::numeric_limits<float>::lowest());
    return value;
}

ConvertedRow Converter::make_row(int z0) {
    // Each window keeps the slices of the previous row it still covers and computes the rest.
    advance_samples(z0);
    const std::int64_t new_cells = cells_.move_to(z0 - band_ - 1);
    tbb::parallel_for(new_cells, cells_.end(), [&](std::int64_t z) { compute_cell_slice(z); });
    block_distances_.move_to(z0 - band_);
    const std::int64_t new_distances = distances_.move_to(z0 - band_);
    tbb::parallel_for(new_distances, distances_.end(), [&](std::int64_t z) {
        compute_distance_slice(z);
        summarise_distance_slice(z);
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
            const int bx = block_x_first_ + static_cast<int>(b % block_x_count_);
            const int by = block_y_first_ + static_cast<int>(b / block_x_count_);
            blocks_[b] = make_block(bx * kLeafDim, by * kLeafDim, z0);
        }
    });
    ConvertedRow row;
    row.z0 = z0;
    for (std::size_t b = 0; b < blocks_.size(); ++b) {
        const int bx = block_x_first_ + static_cast<int>(b % block_x_count_);
        const int by = block_y_first_ + static_cast<int>(b / block_x_count_);
        if (blocks_[b].leaf)
            row.leaves.push_back(std::move(blocks_[b].leaf));
        else if (blocks_[b].tile)
            row.tiles.emplace_back(openvdb::Coord(bx * kLeafDim, by * kLeafDim, z0), blocks_[b].tile_value);
    }
    return row;
}

namespace {

openvdb::math::Transform::Ptr make_transform(const VolumeHeader& header) {
    // OpenVDB multiplies row vectors: world = (i, j, k, 1) * M, so M is the affine transposed.
    openvdb::Mat4d m = openvdb::Mat4d::identity();
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col) m(col, row) = header.index_to_world[row][col];
    try {
        return openvdb::math::Transform::createLinearTransform(m);
    } catch (const openvdb::Exception& e) {
        // OpenVDB refuses a determinant below 3e-15 in absolute terms (math::AffineMap), so
        // a tiny voxel (1e-5 in each direction) fails as well as a singular matrix: tell them
        // apart by the determinant relative to the voxel's sides.
        const openvdb::Mat3d linear = m.getMat3();
        const double det = linear.det();
        const double sides = linear.row(0).length() * linear.row(1).length() * linear.row(2).length();
        if (std::abs(det) > 1e-9 * sides) {
            char volume[32];
            std::snprintf(volume, sizeof volume, "%g", std::abs(det));
            throw FormatError(header.path.string(), "spacing", "voxels of at least 3e-15 cubic units (OpenVDB's limit)",
                              std::string("a voxel of ") + volume + " (give the spacing in a smaller unit)");
        }
        throw FormatError(header.path.string(), "orientation", "an invertible index-to-world affine",
                          std::string("a singular one (") + e.what() + ")");
    }
}

}  // namespace

void fill_outside(ConvertedRow& row, const int (&dims)[3], float background_value) {
    std::vector<Leaf*> border_leaves;  // leaves reaching outside the scan
    for (const auto& leaf : row.leaves)
        if (!block_in_scan(dims, leaf->origin().x(), leaf->origin().y(), leaf->origin().z())) border_leaves.push_back(leaf.get());
    tbb::parallel_for(std::size_t{0}, border_leaves.size(), [&](std::size_t b) {
        Leaf& leaf = *border_leaves[b];
        for (openvdb::Index n = 0; n < Leaf::SIZE; ++n) {
            const openvdb::Coord xyz = leaf.offsetToGlobalCoord(n);
            if (!in_scan(dims, xyz.x(), xyz.y(), xyz.z())) leaf.setValueOnly(n, background_value);
        }
    });
}

openvdb::FloatTree::Ptr tree_of_rows(std::vector<ConvertedRow>& rows, float background_value) {
    auto tree = std::make_shared<openvdb::FloatTree>(background_value);
    for (ConvertedRow& row : rows)
        for (auto& leaf : row.leaves) tree->addLeaf(leaf.release());
    for (const ConvertedRow& row : rows)
        for (const auto& [origin, value] : row.tiles) tree->addTile(1, origin, value, false);
    rows.clear();
    return tree;
}

openvdb::FloatGrid::Ptr Converter::assemble(std::vector<ConvertedRow>& rows, const ScanValues& values) const {
    const float background_value = background(values);
    for (ConvertedRow& row : rows) fill_outside(row, dims_, background_value);
    const openvdb::FloatTree::Ptr tree = tree_of_rows(rows, background_value);

    auto grid = openvdb::FloatGrid::create(tree);
    grid->setTransform(make_transform(header_));
    grid->setName("density");
    grid->setGridClass(openvdb::GRID_UNKNOWN);
    grid->insertMeta(kMetaSourceFile, openvdb::StringMetadata(header_.path.string()));
    if (options_.iso_range)
        grid->insertMeta(kMetaIsoRange, openvdb::Vec2DMetadata(openvdb::Vec2d(iso_lo_, iso_hi_)));
    else
        grid->insertMeta(kMetaIsovalue, openvdb::DoubleMetadata(options_.iso));
    grid->insertMeta(kMetaUnits, openvdb::StringMetadata(header_.units));
    grid->insertMeta(kMetaValueMin, openvdb::DoubleMetadata(values.min));
    grid->insertMeta(kMetaValueMax, openvdb::DoubleMetadata(values.max));
    grid->insertMeta(kMetaScanMin, openvdb::Vec3IMetadata(openvdb::Vec3i(0, 0, 0)));
    grid->insertMeta(kMetaScanMax, openvdb::Vec3IMetadata(openvdb::Vec3i(dims_[0] - 1, dims_[1] - 1, dims_[2] - 1)));
    return grid;
}

}  // namespace vdbmesh::detail

namespace vdbmesh {

openvdb::FloatGrid::Ptr convert_to_grid(SliceReader& source, const ConvertOptions& options) {
    openvdb::initialize();
    detail::check_convert_options(source.header(), options);
    if (source.next_slice() != 0) throw Error("internal: convert_to_grid needs a source at slice 0");
    detail::Converter converter(source, options);
    std::vector<detail::ConvertedRow> rows;
    const double slices = static_cast<double>(source.header().dims[2]);
    for (int z0 = converter.first_row(); z0 <= converter.last_row(); z0 += detail::kLeafDim) {
        rows.push_back(converter.make_row(z0));
        if (options.progress) options.progress(std::clamp((z0 + detail::kLeafDim) / slices, 0.0, 1.0));
    }
    return converter.assemble(rows, converter.values());
}

}  // namespace vdbmesh
