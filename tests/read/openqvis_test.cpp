// OpenQVis .dat reader: the two real headers in shared/data (tab-separated with comments,
// and the canonical one), hand-written variants, and bad headers.

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

float at(const std::vector<float>& samples, const VolumeHeader& h, int x, int y, int z) {
    return samples[static_cast<std::size_t>(x + h.dims[0] * (y + h.dims[1] * z))];
}

TEST(OpenQVisTest, WalnutTabSeparatedHeaderWithComments) {
    VDBMESH_SHARED_DATA(dat, "openqvis_walnut_ct/walnut.dat");
    VolumeSource source = open_volume_source(dat);
    const VolumeHeader h = source.header;
    EXPECT_EQ(h.format, "openqvis");
    EXPECT_EQ(h.dims, (std::array<std::int64_t, 3>{128, 96, 114}));
    EXPECT_EQ(h.type, SampleType::u16);
    EXPECT_EQ(h.byte_order, ByteOrder::little);
    EXPECT_EQ(h.spacing, (std::array<double, 3>{1, 1, 1}));
    EXPECT_TRUE(has_warning(h, "byte order"));
    ASSERT_EQ(source.segments.size(), 1u);
    EXPECT_EQ(source.segments[0].path.filename(), "walnut.raw");

    const auto samples = read_all_samples(std::move(source));
    // Expected values computed independently with Python's struct module from walnut.raw.
    EXPECT_EQ(at(samples, h, 0, 0, 0), 192);
    EXPECT_EQ(at(samples, h, 64, 48, 57), 5353);
    EXPECT_EQ(at(samples, h, 127, 95, 113), 90);
    EXPECT_EQ(at(samples, h, 40, 50, 60), 921);
    EXPECT_EQ(at(samples, h, 100, 20, 30), 842);
    EXPECT_EQ(*std::min_element(samples.begin(), samples.end()), 0);
    EXPECT_EQ(*std::max_element(samples.begin(), samples.end()), 22526);
    EXPECT_EQ(std::accumulate(samples.begin(), samples.end(), 0.0), 2873024118.0);
}

TEST(OpenQVisTest, NucleonCanonicalHeader) {
    VDBMESH_SHARED_DATA(dat, "openqvis_nucleon_sim/nucleon.dat");
    VolumeSource source = open_volume_source(dat);
    const VolumeHeader h = source.header;
    EXPECT_EQ(h.dims, (std::array<std::int64_t, 3>{41, 41, 41}));
    EXPECT_EQ(h.type, SampleType::u8);
    EXPECT_EQ(h.units, "mm");
    EXPECT_FALSE(has_warning(h, "byte order"));  // one-byte samples have none

    const auto samples = read_all_samples(std::move(source));
    EXPECT_EQ(at(samples, h, 20, 20, 20), 8);
    EXPECT_EQ(at(samples, h, 10, 20, 30), 117);
    EXPECT_EQ(at(samples, h, 40, 40, 40), 10);
    EXPECT_EQ(at(samples, h, 15, 25, 20), 166);
    EXPECT_EQ(*std::max_element(samples.begin(), samples.end()), 249);
    EXPECT_EQ(std::accumulate(samples.begin(), samples.end(), 0.0), 2715326.0);
}

TEST(OpenQVisTest, SpacesTabsCommentsAndUnknownKeys) {
    const std::string text =
        "# hand-written\n  ObjectFileName:\ttext_u8.raw  \r\nResolution: 2  2\t2\n"
        "SliceThickness:\t0.5 0.25 2\nFormat: uchar\nObjectModel: I\nGridType: EQUIDISTANT\n";
    const VolumeSource source = detail::parse_openqvis_header(text, testdata("read/hand.dat"));
    EXPECT_EQ(source.header.spacing, (std::array<double, 3>{0.5, 0.25, 2}));
    EXPECT_EQ(source.header.index_to_world[1][1], 0.25);
    EXPECT_EQ(source.segments[0].path, testdata("read/text_u8.raw"));
    EXPECT_EQ(source.segments[0].bytes, 8u);
    const auto samples = read_all_samples(source);
    EXPECT_EQ(samples, (std::vector<float>{65, 66, 67, 68, 69, 70, 71, 72}));  // "ABCDEFGH"
}

TEST(OpenQVisTest, FloatSamples) {
    test::ScratchDir scratch;
    const float values[2] = {1.5f, -2.25f};  // the host is little-endian, like the format
    std::string bytes(sizeof values, '\0');
    std::memcpy(bytes.data(), values, sizeof values);
    test::write_file(scratch / "f.raw", bytes);
    test::write_file(scratch / "f.dat", "ObjectFileName: f.raw\nResolution: 2 1 1\nFormat: FLOAT\n");
    VolumeSource source = open_volume_source(scratch / "f.dat");
    EXPECT_EQ(source.header.type, SampleType::f32);
    EXPECT_TRUE(has_warning(source.header, "SliceThickness"));
    EXPECT_EQ(read_all_samples(std::move(source)), (std::vector<float>{1.5f, -2.25f}));
}

TEST(OpenQVisTest, PlainDataStartingWithTheGzipMagicIsReadAsItIs) {
    test::ScratchDir scratch;
    test::write_file(scratch / "g.raw", std::string("\x1f\x8b\x08\x00", 4));  // 31 139 8 0, not a gzip stream
    test::write_file(scratch / "g.dat", "ObjectFileName: g.raw\nResolution: 4 1 1\nFormat: UCHAR\n");
    EXPECT_EQ(read_all_samples(open_volume_source(scratch / "g.dat")), (std::vector<float>{31, 139, 8, 0}));
}

TEST(OpenQVisTest, BadHeadersNameTheField) {
    const auto parse = [](const std::string& text) {
        return [text] { detail::parse_openqvis_header(text, testdata("read/bad.dat")); };
    };
    const std::string name = "ObjectFileName: text_u8.raw\n";
    const std::string res = "Resolution: 2 2 2\n";
    const std::string format = "Format: UCHAR\n";
    expect_format_error(parse(res + format), "ObjectFileName");
    expect_format_error(parse(name + format), "Resolution");
    expect_format_error(parse(name + res), "Format");
    expect_format_error(parse(name + "Resolution: 2 x 2\n" + format), "Resolution");
    expect_format_error(parse(name + "Resolution: 2 2\n" + format), "Resolution");
    expect_format_error(parse(name + "Resolution: 2 0 2\n" + format), "Resolution");
    expect_format_error(parse(name + "Resolution: 4000000000 4000000000 4000000000\n" + format), "Resolution");
    expect_format_error(parse(name + res + "Format: CHAR\n"), "Format");
    expect_format_error(parse(name + res + format + "SliceThickness: 1 0 1\n"), "SliceThickness");
    expect_format_error(parse(name + res + format + "SliceThickness: 1 one 1\n"), "SliceThickness");
    expect_format_error(parse("ObjectFileName: nothing.raw\n" + res + format), "ObjectFileName");
    expect_format_error(parse(name + "Resolution: 3 3 3\n" + format), "file size");
    expect_format_error(parse(name + res + format + "Format: UCHAR\n"), "Format");
    expect_format_error(parse(name + res + format + "not a field\n"), "line 4");
}

TEST(OpenQVisTest, EveryPrefixOfAHeaderFailsCleanly) {
    const std::string text = "ObjectFileName: text_u8.raw\nResolution: 2 2 2\nSliceThickness: 1 1 1\nFormat: UCHAR\n";
    test::expect_prefixes_fail_cleanly(
        text, [](std::string_view prefix) { detail::parse_openqvis_header(prefix, testdata("read/p.dat")); });
}

}  // namespace
}  // namespace vdbmesh
