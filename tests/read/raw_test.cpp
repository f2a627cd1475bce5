// Headerless raw volumes: one file or a split scan, plain or gzip (several members too), the
// exact-length checks, the --raw-* flags, and the real raw scans of shared/data with values
// computed independently (python3 gzip + struct).

#include <gtest/gtest.h>

#include <algorithm>

#include "binary_test_util.h"
#include "common_options.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/read.h"

namespace vdbmesh {
namespace {

using test::Bytes;

ReadOptions raw_options(std::array<std::int64_t, 3> dims, SampleType type = SampleType::u8,
                        ByteOrder order = ByteOrder::little) {
    ReadOptions options;
    options.raw_dims = dims;
    options.raw_type = type;
    options.raw_byte_order = order;
    return options;
}

/// 0, 1, 2, ... as bytes.
Bytes ramp(std::size_t count, unsigned char first = 0) {
    Bytes bytes(count);
    for (std::size_t i = 0; i < count; ++i) bytes[i] = static_cast<unsigned char>(first + i);
    return bytes;
}

std::vector<float> ramp_floats(std::size_t count) {
    std::vector<float> values(count);
    for (std::size_t i = 0; i < count; ++i) values[i] = static_cast<float>(i);
    return values;
}

std::string read_error(const std::filesystem::path& path, const ReadOptions& options) {
    try {
        auto reader = open_volume(path, options);
        test::read_all(*reader);
    } catch (const FormatError& e) {
        return e.what();
    }
    return "";
}

#define EXPECT_MESSAGE_HAS(message, part) EXPECT_NE((message).find(part), std::string::npos) << (message)

TEST(RawTest, HeaderFromTheOptions) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.raw", Bytes(2 * 3 * 4 * 2));
    ReadOptions options = raw_options({2, 3, 4}, SampleType::u16, ByteOrder::big);
    options.raw_spacing = {0.5, 0.25, 2};
    const VolumeSource source = open_volume_source(dir / "a.raw", options);
    EXPECT_EQ(source.header.format, "raw");
    EXPECT_EQ(source.header.dims, (std::array<std::int64_t, 3>{2, 3, 4}));
    EXPECT_EQ(source.header.type, SampleType::u16);
    EXPECT_EQ(source.header.byte_order, ByteOrder::big);
    EXPECT_EQ(source.header.spacing, (std::array<double, 3>{0.5, 0.25, 2}));
    EXPECT_EQ(source.header.index_to_world, axis_aligned_affine({0.5, 0.25, 2}));
}

TEST(RawTest, HeaderBytesAreSkippedInPlainAndGzipFiles) {
    test::ScratchDir dir;
    const Bytes data = test::concat(test::text_bytes("skip me!"), ramp(27));
    test::write_bytes(dir / "a.raw", data);
    test::write_bytes(dir / "a.raw.gz", test::gzip_bytes(data));
    ReadOptions options = raw_options({3, 3, 3});
    options.raw_header_bytes = 8;
    for (const char* name : {"a.raw", "a.raw.gz"})
        EXPECT_EQ(test::read_all(open_volume_source(dir / name, options), 2), ramp_floats(27)) << name;
}

TEST(RawTest, BigEndianSigned16) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.raw", Bytes{0x80, 0x00, 0xff, 0xfe, 0x0c, 0xc8, 0x7f, 0xff, 0, 0, 0, 1, 0xf8, 0x30, 1, 0});
    const auto values = test::read_all(open_volume_source(dir / "a.raw", raw_options({2, 2, 2}, SampleType::i16, ByteOrder::big)));
    EXPECT_EQ(values, (std::vector<float>{-32768, -2, 3272, 32767, 0, 1, -2000, 256}));
}

TEST(RawTest, SeveralGzipMembersInOneFile) {
    test::ScratchDir dir;
    const Bytes data = ramp(64);
    test::write_bytes(dir / "a.gz", test::concat(test::concat(test::gzip_bytes(Bytes(data.begin(), data.begin() + 10)),
                                                              test::gzip_bytes(Bytes(data.begin() + 10, data.begin() + 40))),
                                                 test::gzip_bytes(Bytes(data.begin() + 40, data.end()))));
    EXPECT_EQ(test::read_all(open_volume_source(dir / "a.gz", raw_options({4, 4, 4})), 3), ramp_floats(64));
}

TEST(RawTest, SplitScanReadsItsPartsInOrder) {
    test::ScratchDir dir;
    const Bytes data = ramp(64);
    // Parts cut mid-slice, one gzipped, one with a header.
    test::write_bytes(dir / "p1", test::concat(Bytes{9, 9}, Bytes(data.begin(), data.begin() + 21)));
    test::write_bytes(dir / "p2.gz", test::gzip_bytes(Bytes(data.begin() + 21, data.begin() + 50)));
    test::write_bytes(dir / "p3", Bytes(data.begin() + 50, data.end()));
    ReadOptions options = raw_options({4, 4, 4});
    options.raw_header_bytes = 2;
    options.raw_more_files = {dir / "p2.gz", dir / "p3"};
    EXPECT_EQ(test::read_all(open_volume_source(dir / "p1", options), 1), ramp_floats(64));
}

TEST(RawTest, PlainFilesOfTheWrongSizeFailWhenOpened) {
    test::ScratchDir dir;
    test::write_bytes(dir / "short.raw", ramp(26));
    test::write_bytes(dir / "long.raw", ramp(28));
    const ReadOptions options = raw_options({3, 3, 3});
    EXPECT_THROW(open_volume_source(dir / "short.raw", options), FormatError);
    std::string message = read_error(dir / "short.raw", options);
    EXPECT_MESSAGE_HAS(message, "expected 27 bytes of samples (3 x 3 x 3 u8)");
    EXPECT_MESSAGE_HAS(message, "only 26 bytes (truncated)");
    EXPECT_THROW(open_volume_source(dir / "long.raw", options), FormatError);
    message = read_error(dir / "long.raw", options);
    EXPECT_MESSAGE_HAS(message, "trailing data");
    EXPECT_MESSAGE_HAS(message, "1 more bytes");
}

TEST(RawTest, SplitPlainPartsTooShortOrTooLong) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a", ramp(20));
    test::write_bytes(dir / "b", ramp(6));
    test::write_bytes(dir / "c", ramp(8));
    ReadOptions options = raw_options({3, 3, 3});
    options.raw_more_files = {dir / "b"};
    EXPECT_MESSAGE_HAS(read_error(dir / "a", options), "only 26 bytes (truncated)");
    EXPECT_MESSAGE_HAS(read_error(dir / "a", options), "in 2 files");
    options.raw_more_files = {dir / "c"};
    EXPECT_MESSAGE_HAS(read_error(dir / "a", options), "trailing data");
}

TEST(RawTest, SplitGzipPartsTooShortOrTooLongFailWhileStreaming) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.gz", test::gzip_bytes(ramp(20)));
    test::write_bytes(dir / "b.gz", test::gzip_bytes(ramp(6)));
    test::write_bytes(dir / "c.gz", test::gzip_bytes(ramp(8)));
    ReadOptions options = raw_options({3, 3, 3});
    options.raw_more_files = {dir / "b.gz"};
    EXPECT_NO_THROW(open_volume_source(dir / "a.gz", options));  // sizes unknown until decompressed
    std::string message = read_error(dir / "a.gz", options);
    EXPECT_MESSAGE_HAS(message, "a.gz: sample data: expected 27 bytes of samples (3 x 3 x 3 u8) in 2 files, got only 26 bytes (truncated)");
    options.raw_more_files = {dir / "c.gz"};
    message = read_error(dir / "a.gz", options);
    EXPECT_MESSAGE_HAS(message, "c.gz: trailing data");
    EXPECT_MESSAGE_HAS(message, "1 more bytes");
}

TEST(RawTest, BadOptionsAndMissingFiles) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.raw", ramp(8));
    ReadOptions options = raw_options({2, 2, 2});
    options.raw_header_bytes = 9;
    EXPECT_MESSAGE_HAS(read_error(dir / "a.raw", options), "--header-bytes: expected at most the file size, 8");
    options = raw_options({2, 2, 2});
    options.raw_more_files = {dir / "missing"};
    EXPECT_MESSAGE_HAS(read_error(dir / "a.raw", options), "missing");
    options = raw_options({2, 0, 2});
    EXPECT_MESSAGE_HAS(read_error(dir / "a.raw", options), "--raw-dims[1]: expected > 0");
    options = raw_options({1 << 30, 1 << 30, 1 << 30}, SampleType::f64);
    EXPECT_MESSAGE_HAS(read_error(dir / "a.raw", options), "63 bits");
    options = raw_options({2, 2, 2});
    options.raw_spacing = {1, -1, 1};
    EXPECT_THROW(open_volume_source(dir / "a.raw", options), UsageError);
}

TEST(RawTest, CommandLineFlagsBecomeReadOptions) {
    cli::ReadFlags flags;
    flags.raw_dims = "512,512,361";
    flags.raw_type = "u16";
    flags.raw_endian = "big";
    flags.spacing = "0.337891,0.337891,0.5";
    flags.header_bytes = 12;
    const ReadOptions options = flags.to_read_options({"part2.raw.gz"});
    EXPECT_EQ(options.raw_dims, (std::array<std::int64_t, 3>{512, 512, 361}));
    EXPECT_EQ(options.raw_type, SampleType::u16);
    EXPECT_EQ(options.raw_byte_order, ByteOrder::big);
    EXPECT_EQ(options.raw_spacing, (std::array<double, 3>{0.337891, 0.337891, 0.5}));
    EXPECT_EQ(options.raw_header_bytes, 12u);
    EXPECT_EQ(options.raw_more_files, std::vector<std::filesystem::path>{"part2.raw.gz"});
    cli::ReadFlags no_dims;
    EXPECT_THROW(no_dims.to_read_options({"part2.raw"}), UsageError);
}

// ---------------------------------------------------------------- real scans

TEST(RawTest, StanfordCtHeadGzipBigEndian) {
    VDBMESH_SHARED_DATA(path, "raw_stanford_cthead/CThead_256x256x113_int16be.raw.gz");
    const VolumeSource source = open_volume_source(path, raw_options({256, 256, 113}, SampleType::i16, ByteOrder::big));
    const std::vector<float> values = test::read_all(source, 10);
    const VolumeHeader& h = source.header;
    EXPECT_EQ(test::voxel(values, h, 128, 128, 56), 2322.0f);
    EXPECT_EQ(test::voxel(values, h, 100, 80, 20), 1069.0f);
    EXPECT_EQ(test::voxel(values, h, 60, 150, 100), 120.0f);
    EXPECT_EQ(test::voxel(values, h, 255, 255, 112), 25.0f);
    EXPECT_EQ(*std::min_element(values.begin(), values.end()), 0.0f);
    EXPECT_EQ(*std::max_element(values.begin(), values.end()), 3272.0f);
}

TEST(RawTest, StanfordCtBunnyInTwoGzipFiles) {
    VDBMESH_SHARED_DATA(part1, "raw_stanford_ct_bunny/bunny_ct_512x512x361_uint16be.part1of2.raw.gz");
    VDBMESH_SHARED_DATA(part2, "raw_stanford_ct_bunny/bunny_ct_512x512x361_uint16be.part2of2.raw.gz");
    ReadOptions options = raw_options({512, 512, 361}, SampleType::u16, ByteOrder::big);
    options.raw_spacing = {0.337891, 0.337891, 0.5};
    options.raw_more_files = {part2};
    auto reader = open_volume(part1, options);
    // Streamed slab by slab (the dense volume is 380 MB as floats): check a few voxels, count
    // the padding outside the field of view, and the range inside it.
    const std::int64_t slice = reader->header().slice_voxels();
    std::vector<float> slab(static_cast<std::size_t>(slice * 19));  // 361 = 19 x 19 slices
    std::int64_t padding = 0;
    float lo = 1e9f, hi = -1e9f;
    auto at = [&](std::int64_t x, std::int64_t y, std::int64_t z_in_slab) {
        return slab[static_cast<std::size_t>(z_in_slab * slice + y * 512 + x)];
    };
    while (reader->next_slice() < 361) {
        const std::int64_t z0 = reader->next_slice();
        reader->read_slices(19, slab.data());
        for (float v : slab) {
            if (v == 63536.0f) ++padding;
            else lo = std::min(lo, v), hi = std::max(hi, v);
        }
        if (z0 == 171) {  // slab 171..189 straddles the two files (slice 180 starts part 2)
            EXPECT_EQ(at(256, 256, 179 - z0), 57.0f);
            EXPECT_EQ(at(256, 256, 180 - z0), 56.0f);
            EXPECT_EQ(at(256, 256, 181 - z0), 55.0f);
        }
        if (z0 == 95) EXPECT_EQ(at(200, 300, 100 - z0), 32.0f);
        if (z0 == 247) EXPECT_EQ(at(300, 250, 250 - z0), 50.0f);
        if (z0 == 285) EXPECT_EQ(at(256, 400, 300 - z0), 2099.0f);
        if (z0 == 342) EXPECT_EQ(at(511, 511, 360 - z0), 63536.0f);
    }
    EXPECT_EQ(padding, 20133692);
    EXPECT_EQ(lo, 0.0f);
    EXPECT_EQ(hi, 4095.0f);
}

TEST(RawTest, VtkHeadsqPlainLittleEndianWholeAndSplitIntoSlices) {
    VDBMESH_SHARED_DATA(path, "raw_vtk_headsq/headsq_64x64x93_int16le.raw");
    VDBMESH_SHARED_DATA(first_slice, "raw_vtk_headsq/slices/quarter.1");
    const ReadOptions options = raw_options({64, 64, 93}, SampleType::i16, ByteOrder::little);
    const VolumeSource source = open_volume_source(path, options);
    const std::vector<float> values = test::read_all(source, 8);
    const VolumeHeader& h = source.header;
    EXPECT_EQ(test::voxel(values, h, 32, 32, 46), 122.0f);
    EXPECT_EQ(test::voxel(values, h, 20, 40, 10), 1077.0f);
    EXPECT_EQ(test::voxel(values, h, 50, 30, 80), 104.0f);
    EXPECT_EQ(*std::min_element(values.begin(), values.end()), 0.0f);
    EXPECT_EQ(*std::max_element(values.begin(), values.end()), 3926.0f);

    // The 93 original slice files as one split scan give the same samples.
    ReadOptions split = options;
    for (int i = 2; i <= 93; ++i) split.raw_more_files.push_back(first_slice.parent_path() / ("quarter." + std::to_string(i)));
    EXPECT_EQ(test::read_all(open_volume_source(first_slice, split), 5), values);
}

}  // namespace
}  // namespace vdbmesh
