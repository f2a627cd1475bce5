#include "vdbmesh/volume_stats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "grid_test_util.h"
#include "test_data.h"
#include "vdbmesh/error.h"

namespace vdbmesh {
namespace {

constexpr std::pair<double, double> kU16{0, 65535};

VolumeStats stats_of(std::vector<float> values, double quantum, std::size_t slab = 97,
                     std::optional<std::pair<double, double>> bounds = {}) {
    VolumeStatsAccumulator accumulator(quantum, bounds);
    for (std::size_t start = 0; start < values.size(); start += slab)
        accumulator.add(values.data() + start, std::min(slab, values.size() - start));
    return accumulator.finish();
}

TEST(VolumeStatsTest, IntegerSamplesGiveExactNearestRankPercentiles) {
    std::vector<float> values(1000);
    for (int i = 0; i < 1000; ++i) values[i] = static_cast<float>(i);
    std::shuffle(values.begin(), values.end(), std::mt19937(7));
    const VolumeStats stats = stats_of(values, 1.0, 97, kU16);
    EXPECT_EQ(stats.count, 1000);
    EXPECT_EQ(stats.min, 0);
    EXPECT_EQ(stats.max, 999);
    EXPECT_DOUBLE_EQ(stats.mean, 499.5);
    EXPECT_EQ(stats.bin_width, 1.0);
    // The k-th smallest sample with k = ceil(p% of 1000): 10th, 50th, 500th, 950th, 990th.
    EXPECT_EQ(stats.percentiles[0], 9);
    EXPECT_EQ(stats.percentiles[1], 49);
    EXPECT_EQ(stats.percentiles[2], 499);
    EXPECT_EQ(stats.percentiles[3], 949);
    EXPECT_EQ(stats.percentiles[4], 989);
}

TEST(VolumeStatsTest, IntegerSamplesWithoutBoundsAreWithinOneBin) {
    std::vector<float> values(1000);
    for (int i = 0; i < 1000; ++i) values[i] = static_cast<float>(i);
    std::shuffle(values.begin(), values.end(), std::mt19937(7));
    const VolumeStats stats = stats_of(values, 1.0);  // the first slab does not span the data
    EXPECT_EQ(stats.min, 0);
    EXPECT_EQ(stats.max, 999);
    EXPECT_LE(stats.bin_width, 2.0);
    EXPECT_NEAR(stats.percentiles[2], 499, stats.bin_width);
}

TEST(VolumeStatsTest, RangeGrowingAfterTheFirstSlabStaysExactForCounts) {
    // The first slab spans 0..10, later ones reach 1e6 (and below zero): the histogram
    // doubles its bins many times; counts stay exact, so percentiles are within a bin.
    std::vector<float> values;
    for (int i = 0; i <= 10; ++i) values.push_back(static_cast<float>(i));
    for (int i = 0; i < 5000; ++i) values.push_back(static_cast<float>(200 * i));
    values.push_back(-3000);
    const VolumeStats stats = stats_of(values, 0.0, 11);
    EXPECT_EQ(stats.min, -3000);
    EXPECT_EQ(stats.max, 999800);
    std::vector<float> sorted = values;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t p = 0; p < kStatsPercentiles.size(); ++p) {
        const auto rank = static_cast<std::size_t>(std::ceil(kStatsPercentiles[p] / 100.0 * sorted.size()));
        EXPECT_NEAR(stats.percentiles[p], sorted[rank - 1], stats.bin_width) << kStatsPercentiles[p] << "%";
    }
    EXPECT_LT(stats.bin_width, (stats.max - stats.min) / 16384);  // at least a quarter of the bins in use
}

TEST(VolumeStatsTest, OtsuSplitsTwoModes) {
    std::mt19937 random(3);
    std::normal_distribution<float> dark(20, 3), bright(200, 5);
    std::vector<float> values;
    for (int i = 0; i < 7000; ++i) values.push_back(std::round(dark(random)));
    for (int i = 0; i < 3000; ++i) values.push_back(std::round(bright(random)));
    const VolumeStats stats = stats_of(values, 1.0, 97, kU16);
    EXPECT_GT(stats.suggested_iso, 40);
    EXPECT_LT(stats.suggested_iso, 180);
    EXPECT_EQ(stats.suggested_iso - std::floor(stats.suggested_iso), 0.5);  // between two integer values
    EXPECT_NE(stats.suggested_reason.find("Otsu"), std::string::npos);
    EXPECT_NE(stats.suggested_reason.find("70.0%"), std::string::npos) << stats.suggested_reason;
}

TEST(VolumeStatsTest, OtsuTakesTheMiddleOfAnEmptyGap) {
    std::vector<float> values(100, 0.0f);
    std::fill(values.begin() + 60, values.end(), 255.0f);
    EXPECT_EQ(stats_of(values, 1.0).suggested_iso, 127.5);
    EXPECT_EQ(stats_of(values, 1.0, 97, kU16).suggested_iso, 127.5);
}

TEST(VolumeStatsTest, OtsuLeavesOutAPaddingSpike) {
    // 25% padding at -2000 (outside a CT's field of view), then air near 0 and material near 1500:
    // plain Otsu would split padding from the rest.
    std::mt19937 random(5);
    std::normal_distribution<float> air(20, 10), material(1500, 100);
    std::vector<float> values(2500, -2000.0f);
    for (int i = 0; i < 5000; ++i) values.push_back(std::round(air(random)));
    for (int i = 0; i < 2500; ++i) values.push_back(std::round(material(random)));
    const VolumeStats stats = stats_of(values, 1.0, 97, std::make_pair(-32768.0, 32767.0));
    EXPECT_GT(stats.suggested_iso, 200);
    EXPECT_LT(stats.suggested_iso, 1200);
    EXPECT_NE(stats.suggested_reason.find("padding"), std::string::npos) << stats.suggested_reason;
    EXPECT_EQ(stats.percentiles[0], -2000);  // percentiles keep every sample
}

TEST(VolumeStatsTest, ConstantVolumeHasNoSurface) {
    const VolumeStats stats = stats_of(std::vector<float>(500, 42.0f), 1.0, 97, kU16);
    EXPECT_EQ(stats.min, 42);
    EXPECT_EQ(stats.max, 42);
    for (double p : stats.percentiles) EXPECT_EQ(p, 42);
    EXPECT_NE(stats.suggested_reason.find("no surface"), std::string::npos);
}

TEST(VolumeStatsTest, ConstantFirstSlabsThenDataKeepsTheirCount) {
    std::vector<float> values(300, 0.0f);
    for (int i = 1; i <= 100; ++i) values.push_back(static_cast<float>(i));
    const VolumeStats stats = stats_of(values, 1.0, 50);
    EXPECT_EQ(stats.percentiles[2], 0);   // 200th of 400: still a zero
    EXPECT_EQ(stats.percentiles[4], 96);  // 396th of 400
}

TEST(VolumeStatsTest, NoSamplesIsAnError) { EXPECT_THROW(VolumeStatsAccumulator().finish(), Error); }

TEST(VolumeStatsTest, StreamsAReaderToTheEnd) {
    test::ScratchDir dir;
    const auto volume = test::make_volume({13, 7, 9}, [](int x, int y, int z) { return static_cast<float>(x * y - z); });
    auto reader = test::write_and_open(volume, dir / "v.raw");
    double last_progress = 0;
    const VolumeStats stats = compute_volume_stats(*reader, [&](double f) { last_progress = f; });
    EXPECT_EQ(reader->next_slice(), 9);
    EXPECT_EQ(last_progress, 1.0);
    EXPECT_EQ(stats.count, 13 * 7 * 9);
    EXPECT_EQ(stats.min, -8);
    EXPECT_EQ(stats.max, 72);
    const VolumeStats direct = stats_of(volume.values, 0.0, volume.values.size());  // one slab, as the reader gives
    EXPECT_EQ(stats.suggested_iso, direct.suggested_iso);
}

}  // namespace
}  // namespace vdbmesh
