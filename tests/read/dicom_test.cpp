// Tests of the DICOM series reader (src/read/dicom.cpp, dicom_parse.cpp) and of the DICOM
// series writer (src/write/write_dicom.cpp) through each other and the real EGSnrc series.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <vector>

#include "write/write_dicom.h"
#include "read/dicom_parse.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/read.h"

namespace vdbmesh {
namespace {

namespace fs = std::filesystem;
using test::ScratchDir;

std::vector<unsigned char> file_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Reads the whole volume (small test volumes only).
std::vector<float> read_all(VolumeReader& reader) {
    std::vector<float> values(static_cast<std::size_t>(reader.header().voxel_count()));
    reader.read_slices(reader.header().dims[2], values.data());
    return values;
}

/// The message of the FormatError @a read throws (fails the test when it throws nothing else).
template <typename F>
std::string format_error_of(F read) {
    try {
        read();
    } catch (const FormatError& error) {
        return error.what();
    }
    ADD_FAILURE() << "no FormatError";
    return "";
}

/// A small oblique right-handed volume: rotation about (1, 2, 3) by 0.4 rad, spacing 0.7, 0.9, 2.5.
VolumeHeader oblique_header(SampleType type) {
    VolumeHeader header;
    header.dims = {6, 5, 4};
    header.type = type;
    header.spacing = {0.7, 0.9, 2.5};
    header.value_scale = 0.5;
    header.value_offset = -1000;
    const double angle = 0.4, n = std::sqrt(14.0);
    const double ux = 1 / n, uy = 2 / n, uz = 3 / n, c = std::cos(angle), s = std::sin(angle);
    const double rotation[3][3] = {{c + ux * ux * (1 - c), ux * uy * (1 - c) - uz * s, ux * uz * (1 - c) + uy * s},
                                   {uy * ux * (1 - c) + uz * s, c + uy * uy * (1 - c), uy * uz * (1 - c) - ux * s},
                                   {uz * ux * (1 - c) - uy * s, uz * uy * (1 - c) + ux * s, c + uz * uz * (1 - c)}};
    const double origin[3] = {-120.25, 33.5, 7.125};
    for (int r = 0; r < 3; ++r) {
        for (int column = 0; column < 3; ++column) header.index_to_world[r][column] = rotation[r][column] * header.spacing[column];
        header.index_to_world[r][3] = origin[r];
    }
    return header;
}

/// Values 0 .. ~1800 with fractions, so that rounding to the stored step (0.5) shows.
float phantom_value(std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<float>(100.3 * x + 37.1 * y + 250.2 * z + 0.3);
}

SliceSource phantom_slices(const VolumeHeader& header) {
    return [header](std::int64_t z, float* slice) {
        for (std::int64_t y = 0; y < header.dims[1]; ++y)
            for (std::int64_t x = 0; x < header.dims[0]; ++x) slice[y * header.dims[0] + x] = phantom_value(x, y, z);
    };
}

/// Writes the oblique phantom, reads it back and compares header and values.
void expect_round_trip(const VolumeHeader& written, const detail::DicomWriteOptions& options) {
    ScratchDir scratch;
    const fs::path folder = scratch / "series";
    detail::write_dicom_series(folder, written, phantom_slices(written), options);
    auto reader = open_volume(folder);
    const VolumeHeader& read = reader->header();
    EXPECT_EQ(read.format, "dicom");
    EXPECT_EQ(read.dims, written.dims);
    EXPECT_EQ(read.type, written.type);
    EXPECT_EQ(read.byte_order, written.byte_order);
    EXPECT_EQ(read.units, "mm");
    EXPECT_DOUBLE_EQ(read.value_scale, written.value_scale);
    EXPECT_DOUBLE_EQ(read.value_offset, written.value_offset);
    // DS values keep 16 characters: about 1e-12 relative on these numbers.
    for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(read.spacing[axis], written.spacing[axis], 1e-9) << axis;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(read.index_to_world[r][c], written.index_to_world[r][c], 1e-9) << r << c;
    const std::vector<float> values = read_all(*reader);
    std::size_t i = 0;
    for (std::int64_t z = 0; z < written.dims[2]; ++z)
        for (std::int64_t y = 0; y < written.dims[1]; ++y)
            for (std::int64_t x = 0; x < written.dims[0]; ++x, ++i)
                // Stored as round((v - offset) / scale): off by at most half a step.
                ASSERT_NEAR(values[i], phantom_value(x, y, z), written.value_scale / 2 + 1e-3) << x << " " << y << " " << z;
}

VolumeHeader axis_aligned_header(std::array<std::int64_t, 3> dims, double value_scale = 1.0) {
    VolumeHeader header;
    header.dims = dims;
    header.type = SampleType::i16;
    header.spacing = {0.5, 0.5, 2.0};
    header.index_to_world = axis_aligned_affine(header.spacing, {10, 20, 30});
    header.value_scale = value_scale;
    return header;
}

void write_series(const fs::path& folder, const VolumeHeader& header, const std::string& series_uid = "") {
    detail::DicomWriteOptions options;
    options.series_uid = series_uid;
    detail::write_dicom_series(folder, header, phantom_slices(header), options);
}

// ---- the real series: bare implicit VR little-endian data sets, named against the z order ----

TEST(DicomSeriesTest, RealSeriesSortedAlongTheNormal) {
    VDBMESH_SHARED_DATA(folder, "dicom_egsnrc_ct_phantom");
    const VolumeSource source = open_volume_source(folder);
    const VolumeHeader& h = source.header;
    EXPECT_EQ(h.format, "dicom");
    EXPECT_EQ(h.dims, (std::array<std::int64_t, 3>{512, 512, 10}));
    EXPECT_EQ(h.type, SampleType::i16);
    EXPECT_EQ(h.byte_order, ByteOrder::little);
    EXPECT_NEAR(h.spacing[0], 0.69, 1e-9);
    EXPECT_NEAR(h.spacing[1], 0.69, 1e-9);
    EXPECT_NEAR(h.spacing[2], 5.0, 1e-6);
    EXPECT_DOUBLE_EQ(h.value_scale, 1.0);
    EXPECT_DOUBLE_EQ(h.value_offset, 0.0);
    // Orientation 1\0\0\0\1\0: the normal is x cross y = +z, so slices run in increasing z
    // and the first one is the lowest, z = -4.5 (file ...16003574, the LAST by name).
    const double expected[3][4] = {{0.69, 0, 0, -176.294998}, {0, 0.69, 0, -176.294998}, {0, 0, 5, -4.5}};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(h.index_to_world[r][c], expected[r][c], 1e-6) << r << c;
    ASSERT_EQ(source.segments.size(), 10u);
    EXPECT_EQ(source.segments.front().path.filename(), "1998052816003574.ct");
    EXPECT_EQ(source.segments.front().offset, 3238u);
    EXPECT_EQ(source.segments[1].path.filename(), "1998052816002208.ct");
    EXPECT_EQ(source.segments[1].offset, 3234u);
    EXPECT_EQ(source.segments.back().path.filename(), "1998052815582995.ct");
    for (const DataSegment& segment : source.segments) EXPECT_EQ(segment.bytes, 512u * 512u * 2u);
}

TEST(DicomSeriesTest, RealSeriesValues) {
    VDBMESH_SHARED_DATA(folder, "dicom_egsnrc_ct_phantom");
    auto reader = open_volume(folder);
    const std::vector<float> values = read_all(*reader);
    const auto at = [&](int x, int y, int z) { return values[(static_cast<std::size_t>(z) * 512 + y) * 512 + x]; };
    // Computed independently with python3 (struct.unpack '<h' at offset 3238/3234 of each
    // file, files ordered by the z of ImagePositionPatient).
    EXPECT_EQ(at(256, 256, 0), 9);
    EXPECT_EQ(at(256, 256, 2), 16);
    EXPECT_EQ(at(256, 256, 5), 19);
    EXPECT_EQ(at(100, 300, 1), -988);
    EXPECT_EQ(at(400, 120, 7), -998);
    EXPECT_EQ(at(0, 0, 9), -1500);
    EXPECT_EQ(at(388, 470, 6), 1439);
    EXPECT_EQ(*std::min_element(values.begin(), values.end()), -1500);
    EXPECT_EQ(*std::max_element(values.begin(), values.end()), 1439);
}

TEST(DicomSeriesTest, RealFileHasNoPreamble) {
    VDBMESH_SHARED_DATA(file, "dicom_egsnrc_ct_phantom/1998052816002208.ct");
    const std::vector<unsigned char> bytes = file_bytes(file);
    ASSERT_GT(bytes.size(), 132u);
    EXPECT_NE(std::string(bytes.begin() + 128, bytes.begin() + 132), "DICM");
    const auto slice = detail::parse_dicom_slice(bytes.data(), bytes.size(), file);
    ASSERT_TRUE(slice.has_value());
    EXPECT_EQ(slice->transfer_syntax, "1.2.840.10008.1.2");
    EXPECT_EQ(slice->pixel_offset, 3234u);
    EXPECT_EQ(slice->pixel_length, 524288u);
    EXPECT_EQ(slice->rows, 512);
    EXPECT_EQ(slice->pixel_representation, 1);
    ASSERT_TRUE(slice->position.has_value());
    EXPECT_NEAR((*slice->position)[2], 0.5, 1e-9);
}

TEST(DicomSeriesTest, TruncatedHeadersNeverCrash) {
    VDBMESH_SHARED_DATA(file, "dicom_egsnrc_ct_phantom/1998052815582995.ct");
    const std::vector<unsigned char> bytes = file_bytes(file);
    // Every cut through the header (and one in the pixels) is skipped as not DICOM or refused
    // with a FormatError; none is accepted.
    for (std::size_t size = 0; size < 3300; size += 7) {
        try {
            EXPECT_FALSE(detail::parse_dicom_slice(bytes.data(), size, file).has_value()) << size;
        } catch (const FormatError&) {
        }
    }
    EXPECT_THROW(detail::parse_dicom_slice(bytes.data(), 300000, file), FormatError);
}

// ---- round trips through the writer ----

TEST(DicomSeriesTest, RoundTripObliqueShuffledNames) {
    detail::DicomWriteOptions options;
    options.shuffle_names = true;
    expect_round_trip(oblique_header(SampleType::i16), options);
}

TEST(DicomSeriesTest, RoundTripBigEndianUnsigned) {
    VolumeHeader header = oblique_header(SampleType::u16);
    header.byte_order = ByteOrder::big;
    expect_round_trip(header, {});
}

TEST(DicomSeriesTest, RoundTripBareDataSets) {
    detail::DicomWriteOptions options;
    options.bare = true;
    expect_round_trip(oblique_header(SampleType::i32), options);
}

TEST(DicomSeriesTest, ShuffledNamesAreNotInPositionOrder) {
    ScratchDir scratch;
    const VolumeHeader header = axis_aligned_header({4, 3, 5});
    detail::DicomWriteOptions options;
    options.shuffle_names = true;
    detail::write_dicom_series(scratch / "s", header, phantom_slices(header), options);
    const VolumeSource source = open_volume_source(scratch / "s");
    std::vector<fs::path> by_position, by_name;
    for (const DataSegment& segment : source.segments) by_position.push_back(segment.path);
    by_name = by_position;
    std::sort(by_name.begin(), by_name.end());
    EXPECT_NE(by_position, by_name);
    EXPECT_NEAR(source.header.index_to_world[2][3], 30, 1e-12);  // the first slice by position
}

TEST(DicomSeriesTest, WrittenFilesArePart10) {
    ScratchDir scratch;
    const VolumeHeader header = axis_aligned_header({4, 3, 2});
    write_series(scratch / "s", header);
    const std::vector<unsigned char> bytes = file_bytes(scratch / "s" / "slice_0000.dcm");
    ASSERT_GT(bytes.size(), 132u);
    EXPECT_EQ(std::string(bytes.begin() + 128, bytes.begin() + 132), "DICM");
    const auto slice = detail::parse_dicom_slice(bytes.data(), bytes.size(), "slice_0000.dcm");
    ASSERT_TRUE(slice.has_value());
    EXPECT_EQ(slice->transfer_syntax, "1.2.840.10008.1.2.1");
    EXPECT_EQ(slice->pixel_offset + slice->pixel_length, bytes.size());
    // PixelSpacing is row spacing \ column spacing: (y, x).
    ASSERT_TRUE(slice->pixel_spacing.has_value());
    EXPECT_DOUBLE_EQ((*slice->pixel_spacing)[0], 0.5);
}

TEST(DicomSeriesTest, AnisotropicPixelSpacingOrder) {
    ScratchDir scratch;
    VolumeHeader header = axis_aligned_header({4, 3, 2});
    header.spacing = {0.25, 0.75, 2};
    header.index_to_world = axis_aligned_affine(header.spacing);
    write_series(scratch / "s", header);
    const std::vector<unsigned char> bytes = file_bytes(scratch / "s" / "slice_0000.dcm");
    const auto slice = detail::parse_dicom_slice(bytes.data(), bytes.size(), "slice_0000.dcm");
    ASSERT_TRUE(slice && slice->pixel_spacing);
    EXPECT_DOUBLE_EQ((*slice->pixel_spacing)[0], 0.75);  // between rows: along y
    EXPECT_DOUBLE_EQ((*slice->pixel_spacing)[1], 0.25);  // between columns: along x
    const VolumeSource source = open_volume_source(scratch / "s");
    EXPECT_DOUBLE_EQ(source.header.spacing[0], 0.25);
    EXPECT_DOUBLE_EQ(source.header.spacing[1], 0.75);
}

TEST(DicomSeriesTest, LeftHandedAffineReadsInNormalOrder) {
    ScratchDir scratch;
    VolumeHeader header = axis_aligned_header({4, 3, 5});
    header.index_to_world[2][2] = -2;  // slices written towards -z, against the normal x cross y
    write_series(scratch / "s", header);
    auto reader = open_volume(scratch / "s");
    // Same world points, k reversed: the reader starts at the lowest slice (z = 30 - 4 * 2).
    EXPECT_NEAR(reader->header().index_to_world[2][2], 2, 1e-12);
    EXPECT_NEAR(reader->header().index_to_world[2][3], 22, 1e-12);
    const std::vector<float> values = read_all(*reader);
    EXPECT_EQ(values[0], std::round(phantom_value(0, 0, 4)));
    EXPECT_EQ(values[4 * 3 * 4], std::round(phantom_value(0, 0, 0)));
}

// ---- folders that are not one clean series ----

TEST(DicomSeriesTest, OtherFilesAreIgnored) {
    ScratchDir scratch;
    const VolumeHeader header = axis_aligned_header({4, 3, 3});
    write_series(scratch / "s", header);
    std::ofstream(scratch / "s" / "README") << "scanned on a Tuesday\n";
    std::ofstream(scratch / "s" / "notes.bin") << std::string("\x08\x00\x05\x00garbage", 12);
    const VolumeSource source = open_volume_source(scratch / "s");
    EXPECT_EQ(source.header.dims[2], 3);
    EXPECT_EQ(source.segments.size(), 3u);
}

TEST(DicomSeriesTest, FolderWithoutDicomIsAnError) {
    ScratchDir scratch;
    fs::create_directory(scratch / "empty");
    std::ofstream(scratch / "empty" / "README") << "nothing here\n";
    const std::string message = format_error_of([&] { open_volume_source(scratch / "empty"); });
    EXPECT_NE(message.find("DICOM files"), std::string::npos) << message;
    EXPECT_NE(message.find("none among 1 files"), std::string::npos) << message;
}

TEST(DicomSeriesTest, MixedSeriesNamesTheField) {
    ScratchDir scratch;
    const VolumeHeader header = axis_aligned_header({4, 3, 3});
    write_series(scratch / "a", header, "1.2.3.4");
    write_series(scratch / "b", header, "1.2.3.5");
    fs::copy_file(scratch / "b" / "slice_0001.dcm", scratch / "a" / "zz_other.dcm");
    const std::string message = format_error_of([&] { open_volume_source(scratch / "a"); });
    EXPECT_NE(message.find((scratch / "a").string()), std::string::npos) << message;
    EXPECT_NE(message.find("SeriesInstanceUID (0020,000E) of zz_other.dcm"), std::string::npos) << message;
    EXPECT_NE(message.find("expected 1.2.3.4"), std::string::npos) << message;
    EXPECT_NE(message.find("got 1.2.3.5"), std::string::npos) << message;
}

TEST(DicomSeriesTest, DifferentRowsIsAnError) {
    ScratchDir scratch;
    write_series(scratch / "a", axis_aligned_header({4, 3, 3}), "1.2.3.4");
    write_series(scratch / "b", axis_aligned_header({4, 6, 3}), "1.2.3.4");
    fs::copy_file(scratch / "b" / "slice_0001.dcm", scratch / "a" / "zz_other.dcm");
    const std::string message = format_error_of([&] { open_volume_source(scratch / "a"); });
    EXPECT_NE(message.find("Rows (0028,0010)"), std::string::npos) << message;
    EXPECT_NE(message.find("expected 3"), std::string::npos) << message;
    EXPECT_NE(message.find("got 6"), std::string::npos) << message;
}

TEST(DicomSeriesTest, MissingSliceNamesTheGap) {
    ScratchDir scratch;
    write_series(scratch / "s", axis_aligned_header({4, 3, 6}));
    fs::remove(scratch / "s" / "slice_0002.dcm");
    const std::string message = format_error_of([&] { open_volume_source(scratch / "s"); });
    EXPECT_NE(message.find("missing slices"), std::string::npos) << message;
    EXPECT_NE(message.find("slice_0001.dcm (32 mm) and slice_0003.dcm (36 mm)"), std::string::npos) << message;
    EXPECT_NE(message.find("a gap of 4 mm"), std::string::npos) << message;
}

TEST(DicomSeriesTest, DuplicatedPositionIsAnError) {
    ScratchDir scratch;
    write_series(scratch / "s", axis_aligned_header({4, 3, 4}));
    fs::copy_file(scratch / "s" / "slice_0002.dcm", scratch / "s" / "copy.dcm");
    const std::string message = format_error_of([&] { open_volume_source(scratch / "s"); });
    EXPECT_NE(message.find("duplicated slice position"), std::string::npos) << message;
}

TEST(DicomSeriesTest, InconsistentRescaleNamesTheField) {
    ScratchDir scratch;
    write_series(scratch / "a", axis_aligned_header({4, 3, 4}, 1.0), "1.2.3.4");
    write_series(scratch / "b", axis_aligned_header({4, 3, 4}, 2.0), "1.2.3.4");
    fs::copy_file(scratch / "b" / "slice_0003.dcm", scratch / "a" / "slice_0003.dcm", fs::copy_options::overwrite_existing);
    const std::string message = format_error_of([&] { open_volume_source(scratch / "a"); });
    EXPECT_NE(message.find("RescaleSlope (0028,1053) of slice_0003.dcm"), std::string::npos) << message;
    EXPECT_NE(message.find("expected 1"), std::string::npos) << message;
    EXPECT_NE(message.find("got 2"), std::string::npos) << message;
}

TEST(DicomSeriesTest, TruncatedSliceIsAnError) {
    ScratchDir scratch;
    write_series(scratch / "s", axis_aligned_header({4, 3, 3}));
    const fs::path file = scratch / "s" / "slice_0001.dcm";
    fs::resize_file(file, fs::file_size(file) - 5);
    const std::string message = format_error_of([&] { open_volume_source(scratch / "s"); });
    EXPECT_NE(message.find("slice_0001.dcm"), std::string::npos) << message;
    EXPECT_NE(message.find("truncated"), std::string::npos) << message;
}

TEST(DicomSeriesTest, ElementsAfterPixelDataAreAllowed) {
    ScratchDir scratch;
    const VolumeHeader header = axis_aligned_header({4, 3, 3});
    write_series(scratch / "s", header);
    // Data Set Trailing Padding (FFFC,FFFC), explicit VR OB, 4 bytes: legal after Pixel Data.
    const char padding[16] = {'\xfc', '\xff', '\xfc', '\xff', 'O', 'B', 0, 0, 4, 0, 0, 0, 0, 0, 0, 0};
    std::ofstream(scratch / "s" / "slice_0001.dcm", std::ios::binary | std::ios::app).write(padding, sizeof padding);
    auto reader = open_volume(scratch / "s");
    const std::vector<float> values = read_all(*reader);
    EXPECT_EQ(values[12 + 4 + 1], 388);  // (1, 1, 1): 100.3 + 37.1 + 250.2 + 0.3 = 387.9, stored rounded
}

TEST(DicomSeriesTest, CompressedTransferSyntaxIsRefused) {
    ScratchDir scratch;
    write_series(scratch / "s", axis_aligned_header({4, 3, 2}));
    // Patch the meta header's TransferSyntaxUID to RLE Lossless (same length, 20 bytes with the NUL pad).
    const fs::path file = scratch / "s" / "slice_0000.dcm";
    std::vector<unsigned char> bytes = file_bytes(file);
    const std::string explicit_le("1.2.840.10008.1.2.1\0", 20), rle("1.2.840.10008.1.2.5\0", 20);
    const auto at = std::search(bytes.begin(), bytes.end(), explicit_le.begin(), explicit_le.end());
    ASSERT_NE(at, bytes.end());
    std::copy(rle.begin(), rle.end(), at);
    std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    const std::string message = format_error_of([&] { open_volume_source(scratch / "s"); });
    EXPECT_NE(message.find("TransferSyntaxUID (0002,0010)"), std::string::npos) << message;
    EXPECT_NE(message.find("1.2.840.10008.1.2.5"), std::string::npos) << message;
}

// ---- corrupt input (found by tests/fuzz/fuzz_dicom.cpp) ----

TEST(DicomSeriesTest, NoCutOfAPart10FileIsAccepted) {
    // GDCM's reader, as Debian builds it (assertions on), aborted the process on most of these.
    ScratchDir scratch;
    VolumeHeader header = axis_aligned_header({4, 3, 2});
    for (const ByteOrder order : {ByteOrder::little, ByteOrder::big}) {
        header.byte_order = order;
        const fs::path folder = scratch / (order == ByteOrder::little ? "le" : "be");
        write_series(folder, header);
        const std::vector<unsigned char> bytes = file_bytes(folder / "slice_0000.dcm");
        std::size_t refused = 0;
        for (std::size_t size = 0; size < bytes.size(); ++size) {
            try {
                // Cut between two elements before Rows, the file reads as DICOM that is not an image.
                EXPECT_FALSE(detail::parse_dicom_slice(bytes.data(), size, "cut.dcm").has_value()) << size;
            } catch (const FormatError&) {
                ++refused;
            }
        }
        EXPECT_GT(refused, bytes.size() / 2);  // every cut inside an element, and every cut after Rows
        EXPECT_TRUE(detail::parse_dicom_slice(bytes.data(), bytes.size(), "whole.dcm").has_value());
    }
}

/// Appends an implicit VR little-endian element (tag, 32-bit length, value).
void add_element(std::string& data, std::uint16_t group, std::uint16_t element, const std::string& value,
                 std::uint32_t length) {
    for (const std::uint32_t number : {std::uint32_t(group) | (std::uint32_t(element) << 16), length})
        for (int byte = 0; byte < 4; ++byte) data += static_cast<char>((number >> (8 * byte)) & 0xff);
    data += value;
}
void add_element(std::string& data, std::uint16_t group, std::uint16_t element, const std::string& value) {
    add_element(data, group, element, value, static_cast<std::uint32_t>(value.size()));
}
const std::string kCtImageStorage("1.2.840.10008.5.1.4.1.1.2\0", 26);
std::string us_value(std::uint16_t value) { return {static_cast<char>(value & 0xff), static_cast<char>(value >> 8)}; }

TEST(DicomSeriesTest, NestedElementsAreSkipped) {
    // A bare implicit VR data set with a sequence of undefined length whose item (of undefined
    // length too) holds a Rows of its own: only the top-level Rows counts.
    std::string data;
    add_element(data, 0x0008, 0x0016, kCtImageStorage);
    add_element(data, 0x0008, 0x1140, "", 0xffffffffu);  // ReferencedImageSequence
    add_element(data, 0xfffe, 0xe000, "", 0xffffffffu);  // item
    add_element(data, 0x0028, 0x0010, us_value(99));
    add_element(data, 0xfffe, 0xe00d, "");  // item delimiter
    add_element(data, 0xfffe, 0xe0dd, "");  // sequence delimiter
    add_element(data, 0x0028, 0x0010, us_value(2));
    add_element(data, 0x0028, 0x0011, us_value(3));
    add_element(data, 0x0028, 0x0100, us_value(8));
    add_element(data, 0x7fe0, 0x0010, "ABCDEF");
    const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
    const auto slice = detail::parse_dicom_slice(bytes, data.size(), "nested.dcm");
    ASSERT_TRUE(slice.has_value());
    EXPECT_EQ(slice->transfer_syntax, "1.2.840.10008.1.2");
    EXPECT_EQ(slice->rows, 2);
    EXPECT_EQ(slice->columns, 3);
    EXPECT_EQ(slice->pixel_offset, data.size() - 6);
    EXPECT_EQ(slice->pixel_length, 6u);
}

TEST(DicomSeriesTest, DeepNestingIsAFormatError) {
    std::string data;
    add_element(data, 0x0008, 0x0016, kCtImageStorage);
    for (int level = 0; level < 10000; ++level) {  // would overflow the stack if followed
        add_element(data, 0x0008, 0x1140, "", 0xffffffffu);
        add_element(data, 0xfffe, 0xe000, "", 0xffffffffu);
    }
    const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
    const std::string message = format_error_of([&] { detail::parse_dicom_slice(bytes, data.size(), "deep.dcm"); });
    EXPECT_NE(message.find("nested more than"), std::string::npos) << message;
}

// ---- the writer's own guarantees ----

TEST(DicomWriterTest, FailedRunLeavesNothing) {
    ScratchDir scratch;
    const VolumeHeader header = axis_aligned_header({4, 3, 5});
    const SliceSource failing = [](std::int64_t z, float* slice) {
        if (z == 3) throw Error("source failed");
        std::fill(slice, slice + 12, 1.0f);
    };
    EXPECT_THROW(detail::write_dicom_series(scratch / "s", header, failing), Error);
    EXPECT_FALSE(fs::exists(scratch / "s"));
    EXPECT_TRUE(fs::is_empty(scratch.path()));
}

TEST(DicomWriterTest, RefusesNonEmptyFolderAndFloats) {
    ScratchDir scratch;
    fs::create_directory(scratch / "full");
    std::ofstream(scratch / "full" / "keep.txt") << "mine\n";
    const VolumeHeader header = axis_aligned_header({4, 3, 2});
    EXPECT_THROW(write_series(scratch / "full", header), Error);
    EXPECT_TRUE(fs::exists(scratch / "full" / "keep.txt"));
    VolumeHeader floats = header;
    floats.type = SampleType::f32;
    EXPECT_THROW(write_series(scratch / "f", floats), Error);
    EXPECT_FALSE(fs::exists(scratch / "f"));
}

TEST(DicomWriterTest, EmptyFolderAndTrailingSlashAccepted) {
    ScratchDir scratch;
    fs::create_directory(scratch / "empty");
    const VolumeHeader header = axis_aligned_header({4, 3, 2});
    write_series(scratch / "empty", header);
    EXPECT_EQ(open_volume_source(scratch / "empty").segments.size(), 2u);
    write_series(scratch.path() / "slash/", header);
    EXPECT_EQ(open_volume_source(scratch / "slash").segments.size(), 2u);
}

TEST(DicomWriterTest, SameHeaderSameBytes) {
    ScratchDir scratch;
    const VolumeHeader header = axis_aligned_header({4, 3, 2});
    write_series(scratch / "a", header);
    write_series(scratch / "b", header);
    EXPECT_EQ(file_bytes(scratch / "a" / "slice_0001.dcm"), file_bytes(scratch / "b" / "slice_0001.dcm"));
}

}  // namespace
}  // namespace vdbmesh
