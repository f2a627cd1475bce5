// NRRD .nrrd/.nhdr reader: the real 93-file headsq header in shared/data, hand-written
// headers in testdata/read (LIST with space directions, attached data with skips, 4-D),
// gzip data made here with zlib, every type name, and bad headers.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>

#include "read/text_formats.h"
#include "test_data.h"
#include "text_reader_test_util.h"
#include "vdbmesh/read.h"

namespace vdbmesh {
namespace {

using test::expect_format_error;
using test::has_warning;
using test::read_all_samples;
using test::testdata;

/// Line skips in the bytes-level tests: every line is taken to be 10 bytes long.
std::uint64_t ten_byte_lines(const std::filesystem::path&, std::uint64_t, std::int64_t lines) {
    return static_cast<std::uint64_t>(lines) * 10;
}

VolumeSource parse(const std::string& text, const std::string& name = "read/test.nhdr") {
    return detail::parse_nrrd_header(text, testdata(name), ten_byte_lines);
}

TEST(NrrdTest, HeadsqSliceFilesEqualTheConcatenatedRaw) {
    VDBMESH_SHARED_DATA(nhdr, "raw_vtk_headsq/slices/quarter.nhdr");
    VDBMESH_SHARED_DATA(raw, "raw_vtk_headsq/headsq_64x64x93_int16le.raw");
    VolumeSource source = open_volume_source(nhdr);
    const VolumeHeader h = source.header;
    EXPECT_EQ(h.format, "nrrd");
    EXPECT_EQ(h.dims, (std::array<std::int64_t, 3>{64, 64, 93}));
    EXPECT_EQ(h.type, SampleType::i16);
    EXPECT_EQ(h.byte_order, ByteOrder::little);
    EXPECT_EQ(h.spacing, (std::array<double, 3>{3.2, 3.2, 1.5}));
    EXPECT_TRUE(has_warning(h, "3D-left-handed"));
    ASSERT_EQ(source.segments.size(), 93u);
    EXPECT_EQ(source.segments[0].path.filename(), "quarter.1");
    EXPECT_EQ(source.segments[92].path.filename(), "quarter.93");
    EXPECT_EQ(source.segments[5].bytes, 8192u);

    // The same samples read as one headerless raw file.
    VolumeSource whole;
    whole.header = h;
    DataSegment segment;
    segment.path = raw;
    whole.segments.push_back(segment);
    const auto samples = read_all_samples(std::move(source));
    EXPECT_EQ(samples, read_all_samples(whole));

    // Expected values computed independently with Python's struct module.
    const auto at = [&](int x, int y, int z) { return samples[static_cast<std::size_t>(x + 64 * (y + 64 * z))]; };
    EXPECT_EQ(at(32, 32, 46), 122);
    EXPECT_EQ(at(10, 40, 80), 101);
    EXPECT_EQ(at(20, 30, 10), 1056);
    EXPECT_EQ(*std::min_element(samples.begin(), samples.end()), 0);
    EXPECT_EQ(*std::max_element(samples.begin(), samples.end()), 3926);
    EXPECT_EQ(std::accumulate(samples.begin(), samples.end(), 0.0), 193392317.0);
}

TEST(NrrdTest, DetachedListWithSpaceDirections) {
    VolumeSource source = open_volume_source(testdata("read/nrrd_list.nhdr"));
    const VolumeHeader& h = source.header;
    EXPECT_EQ(h.dims, (std::array<std::int64_t, 3>{2, 2, 3}));
    // Columns are the space directions, the last column the space origin.
    const Affine expected{{{0, -0.5, 0, 1}, {0.5, 0, 0, 2}, {0, 0, 2, 3}}};
    EXPECT_EQ(h.index_to_world, expected);
    EXPECT_EQ(h.spacing, (std::array<double, 3>{0.5, 0.5, 2}));
    EXPECT_EQ(h.units, "mm");
    EXPECT_TRUE(has_warning(h, "left-posterior-superior"));
    ASSERT_EQ(source.segments.size(), 3u);
    EXPECT_EQ(read_all_samples(std::move(source)),
              (std::vector<float>{65, 66, 67, 68, 69, 70, 71, 72, 73, 74, 75, 76}));
}

TEST(NrrdTest, AttachedFourDimensionalWithLineAndByteSkip) {
    const auto path = testdata("read/nrrd_skip.nrrd");
    VolumeSource source = open_volume_source(path);
    const VolumeHeader& h = source.header;
    EXPECT_EQ(h.dims, (std::array<std::int64_t, 3>{2, 2, 1}));
    EXPECT_EQ(h.type, SampleType::i16);
    EXPECT_EQ(h.byte_order, ByteOrder::big);
    EXPECT_EQ(h.spacing, (std::array<double, 3>{1.5, 1.5, 3}));
    ASSERT_EQ(source.segments.size(), 1u);
    EXPECT_EQ(source.segments[0].file_offset, std::filesystem::file_size(path) - 8);
    // "ABCDEFGH" as big-endian int16: 0x4142, 0x4344, 0x4546, 0x4748.
    EXPECT_EQ(read_all_samples(std::move(source)), (std::vector<float>{16706, 17220, 17734, 18248}));
}

TEST(NrrdTest, GzipAttachedDataStartsAfterTheEmptyLine) {
    test::ScratchDir scratch;
    const std::vector<float> values = {1.5f, -2.0f, 1e6f, 0.25f, -7.0f, 3.0f};
    std::string bytes(values.size() * sizeof(float), '\0');
    std::memcpy(bytes.data(), values.data(), bytes.size());  // the host is little-endian
    const std::string header =
        "NRRD0004\ntype: float\ndimension: 3\nsizes: 3 2 1\nendian: little\nencoding: gzip\nbyte skip: 4\n"
        "space dimension: 3\nspace origin: ( 1, 2 ,3 )\n\n";
    test::write_file(scratch / "g.nrrd", header + test::compress_bytes("skip" + bytes, true));
    VolumeSource source = open_volume_source(scratch / "g.nrrd");
    ASSERT_EQ(source.segments.size(), 1u);
    EXPECT_EQ(source.segments[0].file_offset, header.size());
    EXPECT_EQ(source.segments[0].offset, 4u);
    EXPECT_EQ(source.header.index_to_world, axis_aligned_affine({1, 1, 1}, {1, 2, 3}));
    EXPECT_EQ(read_all_samples(std::move(source)), values);
}

TEST(NrrdTest, GzipDetachedList) {
    test::ScratchDir scratch;
    test::write_file(scratch / "a.raw.gz", test::compress_bytes("ABCD", true));
    test::write_file(scratch / "b.raw.gz", test::compress_bytes("EFGH", true));
    test::write_file(scratch / "l.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: gz\n"
                                         "data file: LIST 2\na.raw.gz\nb.raw.gz\n");
    VolumeSource source = open_volume_source(scratch / "l.nhdr");
    ASSERT_EQ(source.segments.size(), 2u);
    EXPECT_EQ(read_all_samples(std::move(source)), (std::vector<float>{65, 66, 67, 68, 69, 70, 71, 72}));
}

TEST(NrrdTest, PatternWithNegativeStepAndFileDimension) {
    const VolumeSource source =
        parse("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 3\nencoding: raw\n"
              "data file: text_slice%02d.raw 3 1 -1 2\n");
    ASSERT_EQ(source.segments.size(), 3u);
    EXPECT_EQ(source.segments[0].path, testdata("read/text_slice03.raw"));
    EXPECT_EQ(read_all_samples(source), (std::vector<float>{73, 74, 75, 76, 69, 70, 71, 72, 65, 66, 67, 68}));
}

TEST(NrrdTest, ByteSkipMinusOneTakesTheEndOfARawFile) {
    const VolumeSource source = parse("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 1\nencoding: raw\n"
                                      "byte skip: -1\ndata file: text_u16.raw\n");
    EXPECT_EQ(source.segments[0].file_offset, 12u);  // the last 4 of 16 bytes: "a6a7"
    EXPECT_EQ(read_all_samples(source), (std::vector<float>{0x61, 0x36, 0x61, 0x37}));
}

TEST(NrrdTest, EveryScalarTypeName) {
    const std::pair<const char*, SampleType> kNames[] = {
        {"uchar", SampleType::u8},           {"unsigned char", SampleType::u8},
        {"uint8", SampleType::u8},           {"uint8_t", SampleType::u8},
        {"signed char", SampleType::i8},     {"int8", SampleType::i8},
        {"int8_t", SampleType::i8},          {"short", SampleType::i16},
        {"short int", SampleType::i16},      {"signed short", SampleType::i16},
        {"signed  short int", SampleType::i16}, {"int16", SampleType::i16},
        {"int16_t", SampleType::i16},        {"ushort", SampleType::u16},
        {"unsigned short", SampleType::u16}, {"unsigned short int", SampleType::u16},
        {"uint16", SampleType::u16},         {"uint16_t", SampleType::u16},
        {"int", SampleType::i32},            {"signed int", SampleType::i32},
        {"int32", SampleType::i32},          {"int32_t", SampleType::i32},
        {"uint", SampleType::u32},           {"unsigned int", SampleType::u32},
        {"uint32", SampleType::u32},         {"uint32_t", SampleType::u32},
        {"float", SampleType::f32},          {"double", SampleType::f64}};
    for (const auto& [name, type] : kNames) {
        const std::string count = std::to_string(8 / sample_size(type));  // text_u8.raw has 8 bytes
        const VolumeSource source = parse("NRRD0004\ntype: " + std::string(name) + "\ndimension: 3\nsizes: " + count +
                                          " 1 1\nendian: big\nencoding: raw\ndata file: text_u8.raw\n");
        EXPECT_EQ(source.header.type, type) << name;
    }
}

TEST(NrrdTest, BadHeadersNameTheField) {
    const auto parsing = [](const std::string& text) { return [text] { parse(text); }; };
    const std::string magic = "NRRD0004\n", type = "type: uchar\n", dimension = "dimension: 3\n";
    const std::string sizes = "sizes: 2 2 2\n", encoding = "encoding: raw\n", data = "data file: text_u8.raw\n";
    const std::string good = magic + type + dimension + sizes + encoding;
    EXPECT_NO_THROW(parse(good + data));
    expect_format_error(parsing("NRRD0009\n" + type + dimension + sizes + encoding + data), "magic");
    expect_format_error(parsing(""), "magic");
    expect_format_error(parsing(magic + dimension + sizes + encoding + data), "type");
    expect_format_error(parsing(magic + "type: int64\n" + dimension + sizes + encoding + data), "type");
    expect_format_error(parsing(magic + "type: block\n" + dimension + sizes + encoding + data), "type");
    expect_format_error(parsing(magic + type + sizes + encoding + data), "dimension");
    expect_format_error(parsing(magic + type + "dimension: 2\nsizes: 2 4\n" + encoding + data), "dimension");
    expect_format_error(parsing(magic + type + "dimension: 4\nsizes: 2 2 2 1\n" + encoding + data), "sizes");
    expect_format_error(parsing(magic + type + dimension + encoding + data), "sizes");
    expect_format_error(parsing(magic + type + dimension + "sizes: 2 two 2\n" + encoding + data), "sizes");
    expect_format_error(parsing(magic + type + dimension + "sizes: 4611686018427387904 4 4\n" + encoding + data),
                        "sizes");
    expect_format_error(parsing(magic + type + dimension + sizes + data), "encoding");
    expect_format_error(parsing(magic + type + dimension + sizes + "encoding: ascii\n" + data), "encoding");
    expect_format_error(parsing(magic + type + dimension + sizes + "encoding: bzip2\n" + data), "encoding");
    expect_format_error(parsing(magic + "type: short\n" + dimension + "sizes: 2 2 1\n" + encoding + data), "endian");
    expect_format_error(parsing(good + "endian: middle\n" + data), "endian");
    expect_format_error(parsing(good + "data file: nothing.raw\n"), "data file");
    expect_format_error(parsing(good), "data file");
    expect_format_error(parsing(magic + type + dimension + "sizes: 3 3 3\n" + encoding + data), "file size");
    expect_format_error(parsing(good + "space: weird-space\n" + data), "space");
    expect_format_error(parsing(good + "space: RAS-time\n" + data), "space");
    expect_format_error(parsing(good + "space dimension: 2\n" + data), "space dimension");
    expect_format_error(parsing(good + "space directions: (1,0,0) (0,1,0)\n" + data), "space directions");
    expect_format_error(parsing(good + "space directions: (1,0,0) (0,1) (0,0,1)\n" + data), "space directions");
    expect_format_error(parsing(good + "space directions: (1,0,0) none (0,0,1)\n" + data), "space directions");
    expect_format_error(parsing(good + "space directions: (1,0,0) (0,0,0) (0,0,1)\n" + data), "space directions");
    expect_format_error(parsing(good + "space origin: (1,0)\n" + data), "space origin");
    expect_format_error(parsing(good + "spacings: 1 nan 1\n" + data), "spacings");
    expect_format_error(parsing(good + "spacings: 1 1\n" + data), "spacings");
    expect_format_error(parsing(good + "byte skip: -2\n" + data), "byte skip");
    expect_format_error(parsing(magic + type + dimension + sizes + "encoding: gzip\nbyte skip: -1\n" + data),
                        "byte skip");
    expect_format_error(parsing(good + "line skip: -1\n" + data), "line skip");
    expect_format_error(parsing(good + "no colon here\n" + data), "line 6");
    expect_format_error(parsing(good + type + data), "type");

    const std::string slices = magic + type + dimension + "sizes: 2 2 3\n" + encoding;
    expect_format_error(parsing(slices + "data file: text_slice%d.raw 1 3 1\n"), "text_slice1.raw");
    expect_format_error(parsing(slices + "data file: text_slice%02d.raw 1 4 1\n"), "data file");
    expect_format_error(parsing(slices + "data file: LIST\ntext_slice01.raw\ntext_slice02.raw\n"), "data file");
    expect_format_error(parsing(slices + "data file: LIST\ntext_slice01.raw\nmissing.raw\ntext_slice03.raw\n"),
                        "missing.raw");
    expect_format_error(parsing(slices + "data file: LIST 5\ntext_u8.raw\n"), "data file");
}

TEST(NrrdTest, LineSkipPastTheEndOfTheFile) {
    test::ScratchDir scratch;
    test::write_file(scratch / "d.raw", "one line\nABCDEFGH");
    test::write_file(scratch / "s.nhdr", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                                         "line skip: 1\ndata file: d.raw\n");
    EXPECT_EQ(read_all_samples(open_volume_source(scratch / "s.nhdr")),
              (std::vector<float>{65, 66, 67, 68, 69, 70, 71, 72}));
    test::write_file(scratch / "t.nhdr", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                                         "line skip: 2\ndata file: d.raw\n");
    expect_format_error([&] { open_volume_source(scratch / "t.nhdr"); }, "line skip");
}

TEST(NrrdTest, EveryPrefixOfAHeaderFailsCleanly) {
    const std::string text =
        "NRRD0005\n# comment\ntype: unsigned char\ndimension: 3\nsizes: 2 2 3\nspace: RAS\n"
        "space directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\nkey:=value\nencoding: raw\n"
        "line skip: 0\nbyte skip: 0\ndata file: LIST\ntext_slice01.raw\ntext_slice02.raw\ntext_slice03.raw\n";
    test::expect_prefixes_fail_cleanly(text, [](std::string_view prefix) {
        detail::parse_nrrd_header(prefix, testdata("read/p.nhdr"), ten_byte_lines);
    });
}

}  // namespace
}  // namespace vdbmesh
