// One-pass statistics of a scan: value range and mean exactly, percentiles and Otsu's
// threshold from an adaptive histogram.
//
// Otsu, "A Threshold Selection Method from Gray-Level Histograms", IEEE Trans. SMC 9(1), 1979:
// the threshold t maximises the between-class variance w0 * w1 * (mu0 - mu1)^2 of the two
// classes "value <= t" and "value > t" (the same split the converter and meshers use).
//
// The histogram needs a range before the data is known, so it starts with the range of the
// first two distinct values and doubles its bin width whenever a value falls outside. With
// an even bin count, doubling merges bin pairs exactly, so no count is ever approximated.

#include "vdbmesh/volume_stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "vdbmesh/error.h"

namespace vdbmesh {

namespace {

constexpr std::int64_t kSlabSamples = std::int64_t{1} << 22;  // ~16 MB of floats per read

bool is_integer(SampleType type) { return type != SampleType::f32 && type != SampleType::f64; }

/// The raw range of the 8- and 16-bit types (whose every value has a bin of its own).
std::optional<std::pair<double, double>> small_type_range(SampleType type) {
    switch (type) {
        case SampleType::u8: return std::make_pair(0.0, 255.0);
        case SampleType::i8: return std::make_pair(-128.0, 127.0);
        case SampleType::u16: return std::make_pair(0.0, 65535.0);
        case SampleType::i16: return std::make_pair(-32768.0, 32767.0);
        default: return std::nullopt;
    }
}

/// The values the samples of @a header can take, when the type is small.
std::optional<std::pair<double, double>> value_bounds(const VolumeHeader& header) {
    const auto raw = small_type_range(header.type);
    if (!raw) return std::nullopt;
    const double a = raw->first * header.value_scale + header.value_offset;
    const double b = raw->second * header.value_scale + header.value_offset;
    return std::make_pair(std::min(a, b), std::max(a, b));
}

std::string format_number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

std::string format_percent(double fraction) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f%%", 100.0 * fraction);
    return text;
}

}  // namespace

VolumeStatsAccumulator::VolumeStatsAccumulator(double quantum, std::optional<std::pair<double, double>> bounds)
    : quantum_(std::abs(quantum)) {
    // Bins of one value each over the whole range when it fits: no doubling will ever happen.
    if (bounds && quantum_ > 0 && bounds->second > bounds->first &&
        (bounds->second - bounds->first) / quantum_ <= static_cast<double>(kBins) - 1) {
        bins_.assign(kBins, 0);
        width_ = quantum_;
        lo_ = bounds->first - 0.5 * quantum_;
    }
}

void VolumeStatsAccumulator::add(const float* values, std::size_t count) {
    if (count == 0) return;
    const auto [lo_it, hi_it] = std::minmax_element(values, values + count);
    const double lo = *lo_it, hi = *hi_it;
    const bool first = count_ == 0;
    const double previous = min_;  // the pending value while min_ == max_
    min_ = first ? lo : std::min(min_, lo);
    max_ = first ? hi : std::max(max_, hi);
    double sum = 0;
    for (std::size_t i = 0; i < count; ++i) sum += values[i];
    sum_ += sum;
    count_ += static_cast<std::int64_t>(count);

    if (bins_.empty()) {
        if (min_ == max_) {
            pending_count_ += static_cast<std::int64_t>(count);
            return;
        }
        start_histogram(min_, max_);
        if (pending_count_ > 0) bins_[bin_of(previous)] += static_cast<std::uint64_t>(pending_count_);
        pending_count_ = 0;
    }
    cover(lo, hi);
    add_to_bins(values, count);
}

void VolumeStatsAccumulator::start_histogram(double lo, double hi) {
    bins_.assign(kBins, 0);
    if (quantum_ > 0) {
        // Bins centred on the possible values, each holding a power-of-two number of them.
        width_ = quantum_;
        lo_ = lo - 0.5 * quantum_;
        while (hi - lo_ >= static_cast<double>(kBins) * width_) width_ *= 2;
    } else {
        width_ = (hi - lo) / static_cast<double>(kBins - 1);
        lo_ = lo - 0.5 * width_;
    }
}

void VolumeStatsAccumulator::cover(double lo, double hi) {
    const std::size_t half = kBins / 2;
    // Each doubling merges bins (2b, 2b + 1); std::isfinite stops the loop if the width overflows.
    while (lo < lo_ && std::isfinite(width_)) {  // the old range becomes the upper half
        for (std::size_t b = half; b-- > 0;) bins_[half + b] = bins_[2 * b] + bins_[2 * b + 1];  // top down: no overwrite
        std::fill(bins_.begin(), bins_.begin() + half, 0);
        lo_ -= static_cast<double>(kBins) * width_;
        width_ *= 2;
    }
    while (hi >= lo_ + static_cast<double>(kBins) * width_ && std::isfinite(width_)) {  // ... the lower half
        for (std::size_t b = 0; b < half; ++b) bins_[b] = bins_[2 * b] + bins_[2 * b + 1];
        std::fill(bins_.begin() + half, bins_.end(), 0);
        width_ *= 2;
    }
}

std::size_t VolumeStatsAccumulator::bin_of(double value) const {
    const double t = std::floor((value - lo_) / width_);
    if (!(t >= 0)) return 0;  // also catches NaN from an overflowed range
    return t >= static_cast<double>(kBins) ? kBins - 1 : static_cast<std::size_t>(t);
}

void VolumeStatsAccumulator::add_to_bins(const float* values, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) ++bins_[bin_of(values[i])];
}

VolumeStats VolumeStatsAccumulator::finish() const {
    if (count_ == 0) throw Error("volume statistics: no samples");
    VolumeStats stats;
    stats.count = count_;
    stats.min = min_;
    stats.max = max_;
    stats.mean = sum_ / static_cast<double>(count_);
    if (min_ == max_) {
        stats.percentiles.fill(min_);
        stats.suggested_iso = min_;
        stats.suggested_reason = "every sample equals " + format_number(min_) + ": there is no surface at any isovalue";
        return stats;
    }
    stats.bin_width = width_;

    // Percentiles, nearest rank.
    for (std::size_t p = 0; p < kStatsPercentiles.size(); ++p) {
        const auto rank = std::max<std::uint64_t>(
            1, static_cast<std::uint64_t>(std::ceil(kStatsPercentiles[p] / 100.0 * static_cast<double>(count_))));
        std::uint64_t cumulative = 0;
        std::size_t b = 0;
        while (b + 1 < kBins && (cumulative += bins_[b]) < rank) ++b;
        stats.percentiles[p] = std::clamp(bin_centre(b), min_, max_);
    }

    set_otsu_threshold(stats);
    return stats;
}

std::pair<std::size_t, std::size_t> VolumeStatsAccumulator::otsu_span(std::int64_t& padding) const {
    // Scanners fill what lies outside their field of view with one constant far from the data
    // (the bunny CT: -2000 against 0..4095). Otsu would split that spike from everything else,
    // so a spike of at least 1% of the samples at either end of the range, separated from the
    // other values by a gap of at least 10% of the range, is left out.
    constexpr double kSpikeShare = 0.01, kGapShare = 0.1;
    std::size_t first = 0, last = kBins - 1;
    while (bins_[first] == 0) ++first;
    while (bins_[last] == 0) --last;
    const auto gap_bins = static_cast<std::size_t>(std::ceil(kGapShare * (max_ - min_) / width_));
    const auto spike = static_cast<std::uint64_t>(std::ceil(kSpikeShare * static_cast<double>(count_)));
    padding = 0;
    std::size_t next = first + 1;
    while (next < last && bins_[next] == 0) ++next;
    if (bins_[first] >= spike && next - first >= gap_bins && next < last) {
        padding += static_cast<std::int64_t>(bins_[first]);
        first = next;
    }
    std::size_t previous = last - 1;
    while (previous > first && bins_[previous] == 0) --previous;
    if (bins_[last] >= spike && last - previous >= gap_bins && previous > first) {
        padding += static_cast<std::int64_t>(bins_[last]);
        last = previous;
    }
    return {first, last};
}

void VolumeStatsAccumulator::set_otsu_threshold(VolumeStats& stats) const {
    std::int64_t padding = 0;
    const auto [first, last] = otsu_span(padding);
    double total = 0, total_sum = 0;
    for (std::size_t b = first; b <= last; ++b) {
        total += static_cast<double>(bins_[b]);
        total_sum += static_cast<double>(bins_[b]) * bin_centre(b);
    }
    // Scan the split after bin b; ties (runs of empty bins) resolve to the middle of the gap.
    double n0 = 0, sum0 = 0, best = -1;
    std::size_t best_first = first, best_last = first;
    double best_n0 = 0, best_sum0 = 0;
    for (std::size_t b = first; b < last; ++b) {
        n0 += static_cast<double>(bins_[b]);
        sum0 += static_cast<double>(bins_[b]) * bin_centre(b);
        const double n1 = total - n0;
        if (n0 == 0 || n1 == 0) continue;
        const double mean_gap = sum0 / n0 - (total_sum - sum0) / n1;
        const double between = n0 * n1 * mean_gap * mean_gap;
        if (between > best) {
            best = between;
            best_first = best_last = b;
            best_n0 = n0;
            best_sum0 = sum0;
        } else if (b == best_last + 1 && bins_[b] == 0) {
            best_last = b;
        }
    }
    const std::size_t split = (best_first + best_last) / 2;
    stats.suggested_iso = lo_ + static_cast<double>(split + 1) * width_;
    const double n1 = total - best_n0;
    stats.suggested_reason = "Otsu's threshold: the histogram split with the largest between-class variance (at or below: " +
                             format_percent(best_n0 / total) + " of samples, mean " + format_number(best_sum0 / best_n0) +
                             "; above: " + format_percent(n1 / total) + ", mean " +
                             format_number((total_sum - best_sum0) / n1) + ")";
    if (padding > 0)
        stats.suggested_reason += ", leaving out " + format_percent(static_cast<double>(padding) / count_) +
                                  " of samples holding a padding value far from the rest";
}

VolumeStats compute_volume_stats(VolumeReader& reader, const std::function<void(double)>& progress) {
    const VolumeHeader& header = reader.header();
    VolumeStatsAccumulator accumulator(is_integer(header.type) ? header.value_scale : 0.0, value_bounds(header));
    const std::int64_t per_read = std::max<std::int64_t>(1, kSlabSamples / header.slice_voxels());
    std::vector<float> slab;
    while (reader.next_slice() < header.dims[2]) {
        const std::int64_t slices = std::min(per_read, header.dims[2] - reader.next_slice());
        slab.resize(static_cast<std::size_t>(slices * header.slice_voxels()));
        reader.read_slices(slices, slab.data());
        accumulator.add(slab.data(), slab.size());
        if (progress) progress(static_cast<double>(reader.next_slice()) / static_cast<double>(header.dims[2]));
    }
    return accumulator.finish();
}

}  // namespace vdbmesh
