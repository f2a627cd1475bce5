// MetaImage .mhd/.mha reader: hand-written headers in testdata/read (LOCAL, detached,
// MSB, rotation, file pattern, file list), compressed data made here with zlib, bad headers.

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>

#include "read/text_formats.h"
#include "test_data.h"
#include "text_reader_test_util.h"
#include "vdbmesh/error.h"
#include "vdbmesh/read.h"

namespace vdbmesh {
namespace {

using test::expect_format_error;
using test::read_all_samples;
using test::testdata;

std::vector<float> ramp(float first, int count, float step = 1) {
    std::vector<float> values;
    for (int i = 0; i < count; ++i) values.push_back(first + step * static_cast<float>(i));
    return values;
}

/// Little-endian int16 bytes of @a values.
std::string int16_le(const std::vector<int>& values) {
    std::string bytes;
    for (int v : values) {
        const auto u = static_cast<std::uint16_t>(static_cast<std::int16_t>(v));
        bytes += static_cast<char>(u & 0xff);
        bytes += static_cast<char>(u >> 8);
    }
    return bytes;
}

const std::vector<int> kInt16Values = {-300, -1, 0, 1, 2, 255, 256, 1000, 32767, -32768, 7, 12};

std::string int16_header(const std::string& data_lines) {
    return "ObjectType = Image\nNDims = 3\nDimSize = 3 2 2\nElementType = MET_SHORT\n"
           "BinaryDataByteOrderMSB = False\n" +
           data_lines;
}

TEST(MetaImageTest, LocalDataFollowsTheHeader) {
    const auto path = testdata("read/metaimage_local.mha");
    VolumeSource source = open_volume_source(path);
    const VolumeHeader& h = source.header;
    EXPECT_EQ(h.format, "metaimage");
    EXPECT_EQ(h.dims, (std::array<std::int64_t, 3>{2, 2, 2}));
    EXPECT_EQ(h.type, SampleType::u8);
    EXPECT_EQ(h.spacing, (std::array<double, 3>{0.5, 0.5, 2}));
    EXPECT_EQ(h.index_to_world, axis_aligned_affine({0.5, 0.5, 2}, {10, 20, 30}));
    ASSERT_EQ(source.segments.size(), 1u);
    EXPECT_EQ(source.segments[0].path, path);
    EXPECT_EQ(source.segments[0].file_offset, std::filesystem::file_size(path) - 8);
    EXPECT_EQ(read_all_samples(std::move(source)), ramp(65, 8));  // "ABCDEFGH"
}

TEST(MetaImageTest, DetachedLittleEndianWithElementSize) {
    VolumeSource source = open_volume_source(testdata("read/metaimage_u16.mhd"));
    EXPECT_EQ(source.header.type, SampleType::u16);
    EXPECT_EQ(source.header.byte_order, ByteOrder::little);
    EXPECT_EQ(source.header.spacing, (std::array<double, 3>{1.5, 1.5, 3}));
    EXPECT_TRUE(source.header.warnings.empty());
    // text_u16.raw is "a0a1...a7": little-endian sample i is ('0' + i) * 256 + 'a'.
    EXPECT_EQ(read_all_samples(std::move(source)), ramp(0x30 * 256 + 0x61, 8, 256));
}

TEST(MetaImageTest, MostSignificantByteFirst) {
    VolumeSource source = open_volume_source(testdata("read/metaimage_u16_msb.mhd"));
    EXPECT_EQ(source.header.byte_order, ByteOrder::big);
    // Big-endian sample i of "a0a1...a7" is 'a' * 256 + '0' + i.
    EXPECT_EQ(read_all_samples(std::move(source)), ramp(0x61 * 256 + 0x30, 8));
}

TEST(MetaImageTest, TransformMatrixRowsAreAxisDirections) {
    const VolumeSource source = open_volume_source(testdata("read/metaimage_rotated.mhd"));
    const VolumeHeader& h = source.header;
    // TransformMatrix = 0 1 0 / -1 0 0 / 0 0 1: index axis i points along row i
    // (i along +y, j along -x), scaled by ElementSpacing 0.5 0.5 2; Position is voxel 0.
    const Affine expected{{{0, -0.5, 0, 1}, {0.5, 0, 0, 2}, {0, 0, 2, 3}}};
    EXPECT_EQ(h.index_to_world, expected);
    EXPECT_EQ(h.spacing, (std::array<double, 3>{0.5, 0.5, 2}));
    EXPECT_EQ(read_all_samples(source), ramp(65, 8));
}

TEST(MetaImageTest, FilePatternOneSlicePerFile) {
    VolumeSource source = open_volume_source(testdata("read/metaimage_pattern.mhd"));
    ASSERT_EQ(source.segments.size(), 3u);
    EXPECT_EQ(source.segments[2].path.filename(), "text_slice03.raw");
    EXPECT_EQ(source.segments[2].bytes, 4u);
    EXPECT_EQ(read_all_samples(std::move(source)), ramp(65, 12));  // "ABCD" "EFGH" "IJKL"
}

TEST(MetaImageTest, FileListInListedOrder) {
    VolumeSource source = open_volume_source(testdata("read/metaimage_list.mhd"));
    ASSERT_EQ(source.segments.size(), 3u);
    std::vector<float> expected = ramp(73, 4);  // text_slice03.raw first
    for (float v : ramp(69, 4)) expected.push_back(v);
    for (float v : ramp(65, 4)) expected.push_back(v);
    EXPECT_EQ(read_all_samples(std::move(source)), expected);
}

TEST(MetaImageTest, ZlibCompressedLocal) {
    test::ScratchDir scratch;
    const std::string packed = test::compress_bytes(int16_le(kInt16Values), false);
    const std::string header = int16_header("CompressedData = True\nCompressedDataSize = " +
                                            std::to_string(packed.size()) + "\nElementDataFile = LOCAL\n");
    test::write_file(scratch / "z.mha", header + packed);
    VolumeSource source = open_volume_source(scratch / "z.mha");
    ASSERT_EQ(source.segments.size(), 1u);
    EXPECT_EQ(source.segments[0].compression, Compression::zlib);
    EXPECT_EQ(source.segments[0].file_offset, header.size());
    EXPECT_EQ(source.segments[0].bytes, 24u);
    EXPECT_EQ(read_all_samples(std::move(source)), std::vector<float>(kInt16Values.begin(), kInt16Values.end()));
}

// A header from elsewhere must not make us read any file it names (issue 10, point 5): a data
// file outside the header's folder, by ".." or an absolute path, is refused unless allowed.
TEST(MetaImageTest, ADataFileOutsideTheHeadersFolderIsRefusedUnlessAllowed) {
    test::ScratchDir scratch;
    std::filesystem::create_directory(scratch / "scan");
    test::write_file(scratch / "outside.raw", int16_le(kInt16Values));
    test::write_file(scratch / "scan" / "up.mhd", int16_header("ElementDataFile = ../outside.raw\n"));
    test::write_file(scratch / "scan" / "absolute.mhd",
                     int16_header("ElementDataFile = " + std::filesystem::absolute(scratch / "outside.raw").string() + "\n"));
    for (const char* name : {"up.mhd", "absolute.mhd"}) {
        try {
            open_volume_source(scratch / "scan" / name);
            ADD_FAILURE() << name << ": read a data file outside the header's folder";
        } catch (const FormatError& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find("ElementDataFile"), std::string::npos) << message;
            EXPECT_NE(message.find("outside.raw"), std::string::npos) << message;
            EXPECT_NE(message.find("--allow-outside-data"), std::string::npos) << message;
        }
        ReadOptions allowed;
        allowed.allow_outside_data = true;
        EXPECT_EQ(read_all_samples(open_volume_source(scratch / "scan" / name, allowed)),
                  std::vector<float>(kInt16Values.begin(), kInt16Values.end()));
    }
    // Beside the header, and below it, is fine.
    std::filesystem::create_directory(scratch / "scan" / "data");
    test::write_file(scratch / "scan" / "data" / "in.raw", int16_le(kInt16Values));
    test::write_file(scratch / "scan" / "below.mhd", int16_header("ElementDataFile = data/in.raw\n"));
    EXPECT_NO_THROW(open_volume_source(scratch / "scan" / "below.mhd"));
}

TEST(MetaImageTest, ZlibCompressedAtTheEndOfADetachedFile) {
    test::ScratchDir scratch;
    const std::string packed = test::compress_bytes(int16_le(kInt16Values), false);
    test::write_file(scratch / "z.zraw", "junk!" + packed);
    test::write_file(scratch / "z.mhd", int16_header("CompressedData = True\nCompressedDataSize = " +
                                                     std::to_string(packed.size()) +
                                                     "\nHeaderSize = -1\nElementDataFile = z.zraw\n"));
    VolumeSource source = open_volume_source(scratch / "z.mhd");
    EXPECT_EQ(source.segments[0].file_offset, 5u);
    EXPECT_EQ(read_all_samples(std::move(source)), std::vector<float>(kInt16Values.begin(), kInt16Values.end()));
}

TEST(MetaImageTest, HeaderSizeSkipsTheDataFileHeader) {
    test::ScratchDir scratch;
    test::write_file(scratch / "d.raw", std::string(16, 'x') + int16_le(kInt16Values));
    test::write_file(scratch / "d.mhd", int16_header("HeaderSize = 16\nElementDataFile = d.raw\n"));
    test::write_file(scratch / "e.mhd", int16_header("HeaderSize = -1\nElementDataFile = d.raw\n"));
    for (const char* name : {"d.mhd", "e.mhd"}) {
        VolumeSource source = open_volume_source(scratch / name);
        EXPECT_EQ(source.segments[0].file_offset, 16u) << name;
        EXPECT_EQ(read_all_samples(std::move(source)), std::vector<float>(kInt16Values.begin(), kInt16Values.end()));
    }
}

TEST(MetaImageTest, TwoDimensionalImageIsOneSlice) {
    const std::string text = "NDims = 2\nDimSize = 4 2\nElementType = MET_CHAR\nElementSpacing = 0.5 0.25\n"
                             "Offset = 1 2\nTransformMatrix = 0 1 1 0\nElementDataFile = text_u8.raw\n";
    const VolumeSource source = detail::parse_metaimage_header(text, testdata("read/two.mhd"));
    EXPECT_EQ(source.header.dims, (std::array<std::int64_t, 3>{4, 2, 1}));
    EXPECT_EQ(source.header.type, SampleType::i8);
    const Affine expected{{{0, 0.25, 0, 1}, {0.5, 0, 0, 2}, {0, 0, 1, 0}}};
    EXPECT_EQ(source.header.index_to_world, expected);
}

TEST(MetaImageTest, TruncatedCompressedDataFailsWhileReading) {
    test::ScratchDir scratch;
    const std::string packed = test::compress_bytes(int16_le(kInt16Values), false);
    test::write_file(scratch / "t.mha", int16_header("CompressedData = True\nElementDataFile = LOCAL\n") +
                                            packed.substr(0, packed.size() / 2));
    VolumeSource source = open_volume_source(scratch / "t.mha");
    EXPECT_THROW(read_all_samples(std::move(source)), FormatError);
}

TEST(MetaImageTest, BadHeadersNameTheField) {
    const auto parse = [](const std::string& text) {
        return [text] { detail::parse_metaimage_header(text, testdata("read/bad.mhd")); };
    };
    const std::string ndims = "NDims = 3\n", size = "DimSize = 2 2 2\n", type = "ElementType = MET_UCHAR\n";
    const std::string data = "ElementDataFile = text_u8.raw\n";
    EXPECT_NO_THROW(parse(ndims + size + type + data)());
    expect_format_error(parse(size + type + data), "NDims");
    expect_format_error(parse("NDims = 4\n" + size + type + data), "NDims");
    expect_format_error(parse("NDims = three\n" + size + type + data), "NDims");
    expect_format_error(parse(ndims + type + data), "DimSize");
    expect_format_error(parse(ndims + "DimSize = 2 2 two\n" + type + data), "DimSize");
    expect_format_error(parse(ndims + "DimSize = 2 2\n" + type + data), "DimSize");
    expect_format_error(parse(ndims + "DimSize = 4611686018427387904 4 4\n" + type + data), "DimSize");
    expect_format_error(parse(ndims + size + data), "ElementType");
    expect_format_error(parse(ndims + size + "ElementType = MET_LONG_LONG\n" + data), "ElementType");
    expect_format_error(parse(ndims + size + type), "ElementDataFile");
    expect_format_error(parse(ndims + size + type + "ElementDataFile = nothing.raw\n"), "ElementDataFile");
    expect_format_error(parse(ndims + "DimSize = 3 3 3\n" + type + data), "file size");
    expect_format_error(parse(ndims + size + type + "ElementSpacing = 1 0 1\n" + data), "ElementSpacing");
    expect_format_error(parse(ndims + size + type + "TransformMatrix = 1 0 0 0 1 0\n" + data), "TransformMatrix");
    expect_format_error(parse(ndims + size + type + "Offset = 1 x 0\n" + data), "Offset");
    expect_format_error(parse(ndims + size + type + "ElementByteOrderMSB = maybe\n" + data), "ElementByteOrderMSB");
    expect_format_error(parse(ndims + size + type + "ElementNumberOfChannels = 3\n" + data), "ElementNumberOfChannels");
    expect_format_error(parse(ndims + size + type + "BinaryData = False\n" + data), "BinaryData");
    expect_format_error(parse("ObjectType = Mesh\n" + ndims + size + type + data), "ObjectType");
    expect_format_error(parse(ndims + size + type + "HeaderSize = -2\n" + data), "HeaderSize");
    expect_format_error(parse(ndims + size + type + "HeaderSize = -1\nCompressedData = True\n" + data),
                        "CompressedDataSize");
    expect_format_error(parse(ndims + size + type + "CompressedData = True\nCompressedDataSize = 99\n" + data),
                        "CompressedDataSize");
    expect_format_error(parse(ndims + size + type + "no equals sign\n" + data), "line 4");
    expect_format_error(parse(ndims + ndims + size + type + data), "NDims");

    const std::string slices = ndims + "DimSize = 2 2 3\n" + type;
    EXPECT_NO_THROW(parse(slices + "ElementDataFile = text_slice%02d.raw 3 1 -1\n")());
    expect_format_error(parse(slices + "ElementDataFile = text_slice%02d.raw 2 4 1\n"), "text_slice04.raw");
    expect_format_error(parse(slices + "ElementDataFile = text_slice%02d.raw 1 2 1\n"), "ElementDataFile");
    expect_format_error(parse(slices + "ElementDataFile = text_slice%02d.raw 1 3 0\n"), "ElementDataFile");
    expect_format_error(parse(slices + "ElementDataFile = text_slice%s.raw 1 3 1\n"), "ElementDataFile");
    expect_format_error(parse(slices + "ElementDataFile = LIST\ntext_slice01.raw\ntext_slice02.raw\n"),
                        "ElementDataFile");
    expect_format_error(parse(slices + "ElementDataFile = LIST\ntext_slice01.raw\ntext_slice09.raw\ntext_slice02.raw\n"),
                        "text_slice09.raw");
    expect_format_error(parse(slices + "ElementDataFile = LIST 4D\n"), "ElementDataFile");
}

TEST(MetaImageTest, EveryPrefixOfAHeaderFailsCleanly) {
    const std::string text =
        "ObjectType = Image\nNDims = 3\nDimSize = 2 2 3\nElementType = MET_UCHAR\nElementSpacing = 1 1 1\n"
        "TransformMatrix = 1 0 0 0 1 0 0 0 1\nHeaderSize = 0\nElementDataFile = LIST\n"
        "text_slice01.raw\ntext_slice02.raw\ntext_slice03.raw\n";
    test::expect_prefixes_fail_cleanly(
        text, [](std::string_view prefix) { detail::parse_metaimage_header(prefix, testdata("read/p.mhd")); });
}

}  // namespace
}  // namespace vdbmesh
