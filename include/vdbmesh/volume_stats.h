#pragma once
/// @file volume_stats.h
/// @brief Statistics of a scan's samples in one streaming pass (OpenVDB-free): value range,
/// mean, percentiles from an adaptive histogram, and Otsu's threshold as a suggested isovalue.
///
/// N. Otsu, "A Threshold Selection Method from Gray-Level Histograms", IEEE Transactions on
/// Systems, Man, and Cybernetics 9(1), 1979: the threshold maximising the between-class variance.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vdbmesh/read.h"

namespace vdbmesh {

/// The percentiles every VolumeStats reports, in percent.
inline constexpr std::array<double, 5> kStatsPercentiles{1, 5, 50, 95, 99};

/// What one pass over the samples found.
struct VolumeStats {
    std::int64_t count = 0;  ///< samples seen
    double min = 0, max = 0, mean = 0;
    /// Values at kStatsPercentiles (nearest rank: the smallest histogram bin holding at least
    /// p% of the samples at or below it, reported as the bin centre clamped to [min, max]).
    std::array<double, kStatsPercentiles.size()> percentiles{};
    double bin_width = 0;         ///< histogram resolution: percentiles and the threshold are exact to it
    /// Otsu's threshold (a bin edge, between two sample values), computed without a padding
    /// spike: >= 1% of the samples at one end of the range, >= 10% of the range from the rest.
    double suggested_iso = 0;
    std::string suggested_reason; ///< one line saying why
};

/// Accumulates samples slab by slab in bounded memory (a histogram of kBins bins).
/// The histogram's range starts at the values seen first and doubles its bin width (merging
/// bin pairs exactly) whenever a value falls outside, so one pass suffices.
class VolumeStatsAccumulator {
public:
    static constexpr std::size_t kBins = 65536;

    /// @a quantum: the step between distinct sample values (|value_scale| for integer
    /// samples), so that bins hold whole numbers of values; 0 for floating-point samples.
    /// @a bounds: every value the samples can take (8- and 16-bit types), when known: with
    /// fewer than kBins values, each gets a bin from the start and all results are exact.
    explicit VolumeStatsAccumulator(double quantum = 0, std::optional<std::pair<double, double>> bounds = {});

    void add(const float* values, std::size_t count);
    /// Throws Error when no sample was added.
    VolumeStats finish() const;

private:
    void start_histogram(double lo, double hi);
    void cover(double lo, double hi);
    void add_to_bins(const float* values, std::size_t count);
    std::size_t bin_of(double value) const;
    /// The bins Otsu splits: all non-empty ones but a padding spike at either end (counted in @a padding).
    std::pair<std::size_t, std::size_t> otsu_span(std::int64_t& padding) const;
    void set_otsu_threshold(VolumeStats& stats) const;
    double bin_centre(std::size_t bin) const { return lo_ + (static_cast<double>(bin) + 0.5) * width_; }

    double quantum_;
    std::int64_t count_ = 0;
    double min_ = 0, max_ = 0, sum_ = 0;
    // Until two distinct values are seen there is no range to size the bins: count them aside.
    std::int64_t pending_count_ = 0;
    std::vector<std::uint64_t> bins_;  ///< empty until the histogram starts
    double lo_ = 0, width_ = 0;        ///< bin b covers [lo_ + b * width_, lo_ + (b + 1) * width_)
};

/// Reads every remaining slice of @a reader (a few at a time) and returns the statistics.
/// @a progress, when set, is called with the fraction read.
VolumeStats compute_volume_stats(VolumeReader& reader, const std::function<void(double)>& progress = {});

}  // namespace vdbmesh
