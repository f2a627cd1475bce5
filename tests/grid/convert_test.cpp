#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "grid_test_util.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"

namespace vdbmesh {
namespace {

using test::DenseVolume;
using test::ScratchDir;

/// 10 minus the distance to @a centre: above the isovalue 0 inside a ball of radius 10.
DenseVolume ball(const test::Dims& dims, double cx, double cy, double cz, double radius = 10) {
    return test::make_volume(dims, [=](int x, int y, int z) {
        return static_cast<float>(radius - std::sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz)));
    });
}

openvdb::FloatGrid::Ptr convert(const DenseVolume& volume, const ConvertOptions& options) {
    ScratchDir dir;
    auto reader = test::write_and_open(volume, dir / "volume.raw");
    return convert_to_grid(*reader, options);
}

/// Checks the contract of convert_to_grid over the scan and a margin of two leaves around it:
/// the active set is exactly the reference band, voxels in the scan hold their sample when in a
/// leaf and a value on the sample's side of every tested isovalue otherwise, and voxels outside
/// the scan hold the background, which is below every isovalue and every sample.
void expect_contract(const DenseVolume& volume, const openvdb::FloatGrid& grid, double lo, double hi, int band) {
    const test::ReferenceBand reference(volume, lo, hi, band);
    const float background = grid.background();
    EXPECT_LT(background, lo);
    EXPECT_LT(background, *std::min_element(volume.values.begin(), volume.values.end()));
    auto accessor = grid.getConstAccessor();
    int mismatches = 0;
    for (int z = -16; z < volume.dims[2] + 16; ++z)
        for (int y = -16; y < volume.dims[1] + 16; ++y)
            for (int x = -16; x < volume.dims[0] + 16; ++x) {
                const openvdb::Coord xyz(x, y, z);
                const bool on = accessor.isValueOn(xyz);
                const float value = accessor.getValue(xyz);
                bool ok = on == reference.active(x, y, z);
                if (!volume.contains(x, y, z)) {
                    ok = ok && value == background;
                } else if (accessor.probeConstLeaf(xyz)) {
                    ok = ok && value == volume.at(x, y, z);
                } else {
                    for (double iso : {lo, 0.5 * (lo + hi), hi})
                        ok = ok && (value > iso) == (volume.at(x, y, z) > iso);
                }
                if (!ok && ++mismatches <= 5)
                    ADD_FAILURE() << "voxel " << xyz << ": active " << on << " (reference "
                                  << reference.active(x, y, z) << "), value " << value;
            }
    EXPECT_EQ(mismatches, 0);
}

TEST(ConvertTest, ActiveBandAndSidesMatchTheReference) {
    // Dims that are not multiples of 8; the ball crosses the x = 0 and z = 0 faces.
    const DenseVolume volume = ball({21, 19, 17}, 3.5, 9.2, 2.0);
    ConvertOptions options;
    options.iso = 0.25;
    expect_contract(volume, *convert(volume, options), 0.25, 0.25, 1);
}

TEST(ConvertTest, WiderBandMatchesTheReference) {
    const DenseVolume volume = ball({26, 13, 30}, 12.0, 6.5, 14.0);
    ConvertOptions options;
    options.iso = -1.5;
    options.band = 3;
    expect_contract(volume, *convert(volume, options), -1.5, -1.5, 3);
}

TEST(ConvertTest, IsoRangeKeepsEverySurfaceOfTheRange) {
    const DenseVolume volume = ball({24, 24, 24}, 11.0, 12.0, 12.5);
    ConvertOptions options;
    options.iso_range = std::make_pair(-2.0, 3.0);
    const auto grid = convert(volume, options);
    expect_contract(volume, *grid, -2.0, 3.0, 1);
    // Wider than the band of any single isovalue of the range.
    ConvertOptions single;
    single.iso = 0.5;
    EXPECT_GT(grid->activeVoxelCount(), convert(volume, single)->activeVoxelCount());
}

TEST(ConvertTest, IntegerIsovalueOnIntegerSamplesCountsEqualAsOutside) {
    // Samples equal to the isovalue are outside (at or below), so a plateau at the isovalue
    // next to higher values straddles, and one next to lower values does not.
    const DenseVolume volume = test::make_volume({16, 16, 16}, [](int x, int, int) { return x < 5 ? 3.0f : x < 10 ? 7.0f : 9.0f; });
    ConvertOptions options;
    options.iso = 7;
    const auto grid = convert(volume, options);
    expect_contract(volume, *grid, 7, 7, 1);
    EXPECT_TRUE(grid->tree().isValueOn(openvdb::Coord(9, 8, 8)));   // corner of the 7 | 9 cells
    EXPECT_FALSE(grid->tree().isValueOn(openvdb::Coord(5, 8, 8)));  // 3 | 7 cells are all outside
}

TEST(ConvertTest, BlocksFarInsideBecomeTilesOnTheInside) {
    const DenseVolume volume = ball({40, 40, 40}, 20, 20, 20, 15);
    ConvertOptions options;
    options.iso = 0;
    const auto grid = convert(volume, options);
    expect_contract(volume, *grid, 0, 0, 1);
    int inside_tiles = 0;
    for (auto it = grid->tree().cbeginValueOff(); it; ++it)
        if (!it.isVoxelValue() && *it != grid->background()) {  // internal nodes are filled with the background
            EXPECT_GT(*it, 0.0f) << "tile at " << it.getCoord();
            ++inside_tiles;
        }
    EXPECT_GE(inside_tiles, 1);  // [16, 24)^3 lies 8 voxels inside the surface
}

TEST(ConvertTest, WholeVolumeInsideClosesAtTheScanBorder) {
    const DenseVolume volume = test::make_volume({9, 10, 11}, [](int x, int y, int z) { return 5.0f + x + y + z; });
    ConvertOptions options;
    options.iso = 1;
    const auto grid = convert(volume, options);
    expect_contract(volume, *grid, 1, 1, 1);
    EXPECT_TRUE(grid->tree().isValueOn(openvdb::Coord(-1, 0, 0)));  // the virtual ring is active
    EXPECT_TRUE(grid->tree().isValueOn(openvdb::Coord(8, 9, 10)));
}

TEST(ConvertTest, EmptyResultWhenNoSampleIsAboveTheIsovalue) {
    const DenseVolume volume = ball({12, 12, 12}, 6, 6, 6);
    ConvertOptions options;
    options.iso = 100;
    const auto grid = convert(volume, options);
    EXPECT_EQ(grid->activeVoxelCount(), 0u);
    EXPECT_EQ(grid->tree().leafCount(), 0u);
    EXPECT_LT(grid->background(), *std::min_element(volume.values.begin(), volume.values.end()));
}

TEST(ConvertTest, SameGridWhateverTheThreadCount) {
    const DenseVolume volume = ball({37, 29, 33}, 15, 12, 16, 12);
    ConvertOptions options;
    options.iso = 0.1;
    openvdb::FloatGrid::Ptr one, many;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = convert(volume, options);
    }
    many = convert(volume, options);
    ASSERT_EQ(one->tree().leafCount(), many->tree().leafCount());
    EXPECT_EQ(one->background(), many->background());
    auto a = one->tree().cbeginLeaf();
    auto b = many->tree().cbeginLeaf();
    for (; a && b; ++a, ++b) {
        ASSERT_EQ(a->origin(), b->origin());
        EXPECT_EQ(a->getValueMask(), b->getValueMask());
        EXPECT_TRUE(std::equal(a->buffer().data(), a->buffer().data() + a->SIZE, b->buffer().data()));
    }
}

TEST(ConvertTest, TransformFollowsTheHeaderAffine) {
    ScratchDir dir;
    const DenseVolume volume = ball({12, 10, 8}, 6, 5, 4, 3);
    auto reader = test::write_and_open(volume, dir / "volume.raw");
    // A rotation about z by 30 degrees, anisotropic spacing, an origin.
    VolumeSource source{reader->header(), {}};
    source.segments.push_back(DataSegment{dir / "volume.raw"});
    source.segments.back().bytes = volume.values.size() * sizeof(float);
    const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
    source.header.index_to_world = {{{0.5 * c, -0.7 * s, 0, 10}, {0.5 * s, 0.7 * c, 0, -20}, {0, 0, 1.25, 3}}};
    VolumeReader rotated(source);
    ConvertOptions options;
    const auto grid = convert_to_grid(rotated, options);
    const auto& m = source.header.index_to_world;
    for (const openvdb::Coord ijk : {openvdb::Coord(0, 0, 0), openvdb::Coord(3, 7, 5), openvdb::Coord(-2, 11, 9)}) {
        const openvdb::Vec3d world = grid->indexToWorld(ijk);
        for (int r = 0; r < 3; ++r)
            EXPECT_NEAR(world[r], m[r][0] * ijk.x() + m[r][1] * ijk.y() + m[r][2] * ijk.z() + m[r][3], 1e-9);
    }
}

TEST(ConvertTest, MetadataDescribesTheSource) {
    ScratchDir dir;
    const DenseVolume volume = ball({20, 12, 9}, 10, 6, 4, 4);
    auto reader = test::write_and_open(volume, dir / "volume.raw");
    ConvertOptions options;
    options.iso = 1.5;
    const auto grid = convert_to_grid(*reader, options);
    EXPECT_EQ(grid->getName(), "density");
    EXPECT_NE(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_EQ(grid->metaValue<std::string>(kMetaSourceFile), (dir / "volume.raw").string());
    EXPECT_EQ(stored_isovalue(*grid), 1.5);
    EXPECT_EQ(grid->metaValue<double>(kMetaValueMin), *std::min_element(volume.values.begin(), volume.values.end()));
    EXPECT_EQ(grid->metaValue<double>(kMetaValueMax), *std::max_element(volume.values.begin(), volume.values.end()));
    EXPECT_EQ(grid->metaValue<openvdb::Vec3i>(kMetaScanMin), openvdb::Vec3i(0, 0, 0));
    EXPECT_EQ(grid->metaValue<openvdb::Vec3i>(kMetaScanMax), openvdb::Vec3i(19, 11, 8));
    EXPECT_NO_THROW(grid->metaValue<std::string>(kMetaUnits));

    ConvertOptions range;
    range.iso_range = std::make_pair(1.0, 2.0);
    const auto ranged = convert(volume, range);
    EXPECT_FALSE(stored_isovalue(*ranged));
    EXPECT_EQ(ranged->metaValue<openvdb::Vec2d>(kMetaIsoRange), openvdb::Vec2d(1.0, 2.0));
}

TEST(ConvertTest, ProgressReachesOne) {
    const DenseVolume volume = ball({10, 10, 30}, 5, 5, 15, 4);
    ConvertOptions options;
    double last = -1;
    bool monotone = true;
    options.progress = [&](double f) {
        monotone = monotone && f >= last && f >= 0 && f <= 1;
        last = f;
    };
    convert(volume, options);
    EXPECT_TRUE(monotone);
    EXPECT_EQ(last, 1.0);
}

TEST(ConvertTest, BadOptionsAreUsageErrors) {
    const DenseVolume volume = ball({8, 8, 8}, 4, 4, 4, 2);
    ConvertOptions options;
    options.band = 0;
    EXPECT_THROW(convert(volume, options), UsageError);
    options.band = 1;
    options.iso_range = std::make_pair(3.0, 1.0);
    EXPECT_THROW(convert(volume, options), UsageError);
    options.iso_range.reset();
    options.iso = std::numeric_limits<double>::infinity();
    EXPECT_THROW(convert(volume, options), UsageError);
}

TEST(ConvertTest, NonFiniteSampleIsFormatError) {
    DenseVolume volume = ball({8, 8, 20}, 4, 4, 4, 2);
    volume.values[8 * 8 * 17 + 3] = std::numeric_limits<float>::quiet_NaN();
    ConvertOptions options;
    EXPECT_THROW(convert(volume, options), FormatError);
}

TEST(ConvertTest, TooLargeDimsAreRejectedBeforeReading) {
    ScratchDir dir;
    VolumeSource source;
    source.header.path = dir / "huge.raw";
    source.header.dims = {std::int64_t{1} << 32, 1, 1};
    source.segments.push_back(DataSegment{dir / "huge.raw"});
    VolumeReader reader(source);
    EXPECT_THROW(convert_to_grid(reader, ConvertOptions{}), FormatError);
}

TEST(ConvertTest, BunnyCtFromTwoGzipParts) {
    VDBMESH_SHARED_DATA(part1, "raw_stanford_ct_bunny/bunny_ct_512x512x361_uint16be.part1of2.raw.gz");
    ReadOptions read;
    read.raw_dims = std::array<std::int64_t, 3>{512, 512, 361};
    read.raw_type = SampleType::i16;
    read.raw_byte_order = ByteOrder::big;
    read.raw_spacing = {0.337891, 0.337891, 0.5};
    read.raw_more_files = {part1.parent_path() / "bunny_ct_512x512x361_uint16be.part2of2.raw.gz"};
    auto reader = open_volume(part1, read);
    ConvertOptions options;
    options.iso = 1200.5;
    const auto grid = convert_to_grid(*reader, options);
    // SOURCES.md: values 0..4095 in the field of view, -2000 padding outside it.
    EXPECT_EQ(grid->metaValue<double>(kMetaValueMin), -2000);
    EXPECT_EQ(grid->metaValue<double>(kMetaValueMax), 4095);
    EXPECT_EQ(grid->metaValue<openvdb::Vec3i>(kMetaScanMax), openvdb::Vec3i(511, 511, 360));
    // A thin shell: DESIGN.md measured 5.9% of the voxels in a one-voxel band (box dilation);
    // the face dilation used here keeps fewer, but the same order.
    const double share = static_cast<double>(grid->activeVoxelCount()) / (512.0 * 512 * 361);
    EXPECT_GT(share, 0.03);
    EXPECT_LT(share, 0.07);
    EXPECT_LT(grid->memUsage(), 100u << 20);  // DESIGN.md: 54 MB
    EXPECT_DOUBLE_EQ(grid->voxelSize().z(), 0.5);
}

}  // namespace
}  // namespace vdbmesh
