// NIfTI-1 and Analyze 7.5: tiny hand-made files (testdata/read, made by
// make_binary_headers.py), headers built byte by byte for every bad field, and the real
// scans of shared/data with values computed independently (python3 struct/gzip).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>

#include "binary_test_util.h"
#include "read/nifti_header.h"
#include "vdbmesh/parse_util.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/read.h"

namespace vdbmesh {
namespace {

using test::Bytes;

// Header byte offsets (nifti1.h), as the tests set them.
constexpr std::size_t kDim = 40, kDatatype = 70, kBitpix = 72, kPixdim = 76, kVoxOffset = 108, kSclSlope = 112,
                      kQformCode = 252, kSformCode = 254, kQuatern = 256, kSrow = 280, kMagic = 344;

/// A 348-byte header written field by field.
class HeaderBytes {
public:
    explicit HeaderBytes(ByteOrder order = ByteOrder::little) : bytes_(348), order_(order) { i32(0, 348); }

    HeaderBytes& i16(std::size_t at, std::int16_t v) { return put(at, v); }
    HeaderBytes& i32(std::size_t at, std::int32_t v) { return put(at, v); }
    HeaderBytes& f32(std::size_t at, float v) { return put(at, v); }
    HeaderBytes& text(std::size_t at, const std::string& s) {
        std::memcpy(bytes_.data() + at, s.data(), s.size());
        return *this;
    }
    HeaderBytes& dims(std::initializer_list<std::int16_t> dims) {
        i16(kDim, static_cast<std::int16_t>(dims.size()));
        std::size_t at = kDim + 2;
        for (std::int16_t d : dims) i16(at, d), at += 2;
        return *this;
    }
    const Bytes& bytes() const { return bytes_; }

private:
    template <typename T>
    HeaderBytes& put(std::size_t at, T v) {
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, &v, sizeof(T));
        if (order_ == ByteOrder::big) std::reverse(raw, raw + sizeof(T));  // the test hosts are little-endian
        std::memcpy(bytes_.data() + at, raw, sizeof(T));
        return *this;
    }
    Bytes bytes_;
    ByteOrder order_;
};

/// A valid single-file NIfTI-1 header: 2x2x2 u8, pixdim 1, no qform/sform.
HeaderBytes nifti_header(ByteOrder order = ByteOrder::little) {
    HeaderBytes h(order);
    h.dims({2, 2, 2}).i16(kDatatype, 2).i16(kBitpix, 8).f32(kVoxOffset, 352).text(kMagic, std::string("n+1\0", 4));
    for (int i = 0; i < 4; ++i) h.f32(kPixdim + 4 * i, 1);
    return h;
}

/// Header + 4-byte extension flag + samples.
Bytes nii_file(const HeaderBytes& header, const Bytes& samples) {
    return test::concat(test::concat(header.bytes(), Bytes(4, 0)), samples);
}

std::string parse_error(const HeaderBytes& header) {
    try {
        detail::parse_nifti_analyze_header(header.bytes().data(), header.bytes().size(), "test.nii");
    } catch (const FormatError& e) {
        return e.what();
    }
    return "";
}

std::string open_error(const std::filesystem::path& path) {
    try {
        test::read_all(open_volume_source(path));
    } catch (const FormatError& e) {
        return e.what();
    }
    return "";
}

#define EXPECT_MESSAGE_HAS(message, part) EXPECT_NE((message).find(part), std::string::npos) << (message)

void expect_affine_near(const Affine& got, const Affine& expected, double tolerance) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(got[r][c], expected[r][c], tolerance) << "row " << r << " col " << c;
}

// ---------------------------------------------------------------- hand-made files

TEST(NiftiAnalyzeTest, BigEndianAnalyzePairWithSpmScaleAndOrigin) {
    for (const char* name : {"analyze_be_i16.hdr", "analyze_be_i16.img"}) {
        const VolumeSource source = open_volume_source(test::testdata(std::string("read/") + name));
        const VolumeHeader& h = source.header;
        EXPECT_EQ(h.format, "analyze");
        EXPECT_EQ(h.path.filename(), name);
        EXPECT_EQ(h.dims, (std::array<std::int64_t, 3>{4, 3, 2}));
        EXPECT_EQ(h.type, SampleType::i16);
        EXPECT_EQ(h.byte_order, ByteOrder::big);
        EXPECT_EQ(h.spacing, (std::array<double, 3>{1.5, 2, 2.5}));
        EXPECT_EQ(h.units, "mm");
        EXPECT_EQ(h.value_scale, 0.5);
        // originator (2, 3, 1) is world 0: origin = -spacing * (originator - 1).
        expect_affine_near(h.index_to_world, axis_aligned_affine({1.5, 2, 2.5}, {-1.5, -4, 0}), 0);
        const std::vector<float> values = test::read_all(source);
        for (int z = 0; z < 2; ++z)
            for (int y = 0; y < 3; ++y)
                for (int x = 0; x < 4; ++x)
                    EXPECT_EQ(test::voxel(values, h, x, y, z), 0.5f * (x + 10 * y + 100 * z - 50));
    }
}

TEST(NiftiAnalyzeTest, NiftiPairUsesTheSformFromEitherFile) {
    for (const char* name : {"nifti_pair_f32.hdr", "nifti_pair_f32.img"}) {
        const VolumeSource source = open_volume_source(test::testdata(std::string("read/") + name));
        const VolumeHeader& h = source.header;
        EXPECT_EQ(h.format, "nifti");
        EXPECT_EQ(h.type, SampleType::f32);
        EXPECT_EQ(h.units, "mm");
        expect_affine_near(h.index_to_world, Affine{{{0, -2, 0, 5}, {1, 0, 0, 6}, {0, 0, 3, 7}}}, 0);
        EXPECT_EQ(h.spacing, (std::array<double, 3>{1, 2, 3}));  // column norms
        const std::vector<float> values = test::read_all(source);
        EXPECT_EQ(test::voxel(values, h, 2, 1, 1), 0.25f * (2 + 3 + 6) - 1);
        EXPECT_EQ(test::voxel(values, h, 0, 0, 0), -1.0f);
    }
}

TEST(NiftiAnalyzeTest, QformQuaternionWithNegativeQfac) {
    const VolumeSource source = open_volume_source(test::testdata("read/nifti_qform_u16.nii"));
    const VolumeHeader& h = source.header;
    EXPECT_EQ(h.type, SampleType::u16);
    EXPECT_EQ(h.units, "um");
    // 90 degrees about z times diag(1, 2, qfac * 3) with qfac = -1, plus qoffset. The
    // quaternion is stored as float, so the matrix is exact to float precision only.
    expect_affine_near(h.index_to_world, Affine{{{0, -2, 0, 10}, {1, 0, 0, 20}, {0, 0, -3, 30}}}, 1e-6);
    EXPECT_NEAR(h.spacing[1], 2, 1e-6);
    EXPECT_EQ(h.value_scale, 2);
    EXPECT_EQ(h.value_offset, -1);
    const std::vector<float> values = test::read_all(source);
    EXPECT_EQ(test::voxel(values, h, 2, 1, 1), 2.0f * (60000 + 2 + 3 + 6) - 1);
}

TEST(NiftiAnalyzeTest, FourDimensionalImageReadsTheFirstVolumeWithAWarning) {
    const VolumeSource source = open_volume_source(test::testdata("read/nifti_4d_u8.nii.gz"));
    const VolumeHeader& h = source.header;
    EXPECT_EQ(h.dims, (std::array<std::int64_t, 3>{2, 2, 2}));
    ASSERT_EQ(h.warnings.size(), 1u);
    EXPECT_MESSAGE_HAS(h.warnings[0], "3 volumes");
    expect_affine_near(h.index_to_world, axis_aligned_affine({0.5, 0.5, 0.5}), 0);
    const std::vector<float> values = test::read_all(source);
    for (int i = 0; i < 8; ++i) EXPECT_EQ(values[i], static_cast<float>(i)) << i;  // x + 2y + 4z of volume 0
}

TEST(NiftiAnalyzeTest, EveryDatatypeInBothByteOrders) {
    struct Case {
        std::int16_t code, bitpix;
        SampleType type;
    };
    const Case cases[] = {{2, 8, SampleType::u8},     {4, 16, SampleType::i16},  {8, 32, SampleType::i32},
                          {16, 32, SampleType::f32},  {64, 64, SampleType::f64}, {256, 8, SampleType::i8},
                          {512, 16, SampleType::u16}, {768, 32, SampleType::u32}};
    for (const Case& c : cases) {
        for (ByteOrder order : {ByteOrder::little, ByteOrder::big}) {
            test::ScratchDir dir;
            HeaderBytes header = nifti_header(order);
            header.i16(kDatatype, c.code).i16(kBitpix, c.bitpix);
            // Samples 0..7 in the header's byte order: the value in the last byte (big) or first (little).
            const std::size_t size = sample_size(c.type);
            Bytes samples(8 * size, 0);
            for (std::size_t i = 0; i < 8; ++i) {
                double value = static_cast<double>(i);
                Bytes raw(size, 0);
                if (c.type == SampleType::f32) {
                    const float f = static_cast<float>(value);
                    std::memcpy(raw.data(), &f, 4);
                } else if (c.type == SampleType::f64) {
                    std::memcpy(raw.data(), &value, 8);
                } else {
                    raw[0] = static_cast<unsigned char>(i);
                }
                if (order == ByteOrder::big) std::reverse(raw.begin(), raw.end());
                std::copy(raw.begin(), raw.end(), samples.begin() + static_cast<std::ptrdiff_t>(i * size));
            }
            test::write_bytes(dir / "t.nii", nii_file(header, samples));
            const VolumeSource source = open_volume_source(dir / "t.nii");
            EXPECT_EQ(source.header.type, c.type);
            EXPECT_EQ(source.header.byte_order, order);
            const std::vector<float> values = test::read_all(source);
            for (int i = 0; i < 8; ++i) EXPECT_EQ(values[i], static_cast<float>(i)) << c.code << " #" << i;
        }
    }
}

TEST(NiftiAnalyzeTest, ParserNeverTouchesTheDisk) {
    const HeaderBytes header = nifti_header();
    const auto parsed =
        detail::parse_nifti_analyze_header(header.bytes().data(), header.bytes().size(), "/no/such/dir/x.nii");
    EXPECT_TRUE(parsed.single_file);
    EXPECT_EQ(parsed.vox_offset, 352u);
    EXPECT_EQ(parsed.volume_bytes, 8u);
}

TEST(NiftiAnalyzeTest, SlopeZeroOrNotFiniteMeansNoScaling) {
    for (float slope : {0.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        HeaderBytes header = nifti_header();
        header.f32(kSclSlope, slope).f32(kSclSlope + 4, 5);
        const auto parsed = detail::parse_nifti_analyze_header(header.bytes().data(), header.bytes().size(), "t.nii");
        EXPECT_EQ(parsed.header.value_scale, 1);
        EXPECT_EQ(parsed.header.value_offset, 0);
    }
}

// ---------------------------------------------------------------- bad headers and files

TEST(NiftiAnalyzeTest, BadHeaderFieldsAreNamed) {
    struct Case {
        std::function<void(HeaderBytes&)> spoil;
        std::vector<std::string> parts;
    };
    const float kNan = std::numeric_limits<float>::quiet_NaN();
    const float kInf = std::numeric_limits<float>::infinity();
    const std::vector<Case> cases = {
        {[](HeaderBytes& h) { h.i32(0, 349); }, {"sizeof_hdr", "349"}},
        {[](HeaderBytes& h) { h.i32(0, 540); }, {"sizeof_hdr", "NIfTI-2"}},
        {[](HeaderBytes& h) { h.i16(kDim, 0); }, {"dim[0]", "1..7"}},
        {[](HeaderBytes& h) { h.i16(kDim, 8); }, {"dim[0]", "got 8"}},
        {[](HeaderBytes& h) { h.i16(kDim + 4, -3); }, {"dim[2]", "> 0", "-3"}},
        {[](HeaderBytes& h) { h.i16(kDim + 6, 0); }, {"dim[3]", "got 0"}},
        {[](HeaderBytes& h) { h.i16(kDatatype, 1234); }, {"datatype", "1234 (unknown type)"}},
        {[](HeaderBytes& h) { h.i16(kDatatype, 32); }, {"datatype", "32 (unknown type)"}},  // complex64
        {[](HeaderBytes& h) { h.i16(kBitpix, 16); }, {"bitpix", "8 for datatype 2", "got 16"}},
        {[](HeaderBytes& h) { h.dims({32767, 32767, 32767, 32767, 32767, 32767, 32767}); }, {"dim", "63 bits"}},
        {[](HeaderBytes& h) { h.f32(kVoxOffset, 348); }, {"vox_offset", ">= 352", "348"}},
        {[](HeaderBytes& h) { h.f32(kVoxOffset, -352); }, {"vox_offset", "-352"}},
        {[](HeaderBytes& h) { h.f32(kVoxOffset, 352.5f); }, {"vox_offset", "whole number"}},
        {[kNan](HeaderBytes& h) { h.f32(kVoxOffset, kNan); }, {"vox_offset", "nan"}},
        {[kNan](HeaderBytes& h) { h.f32(kPixdim + 4, kNan); }, {"pixdim[1]", "finite"}},
        {[kInf](HeaderBytes& h) { h.f32(kPixdim, -kInf); }, {"pixdim[0]", "finite"}},
        {[](HeaderBytes& h) { h.f32(kPixdim + 8, 0); }, {"pixdim[2]", "non-zero"}},
        {[kInf](HeaderBytes& h) { h.i16(kSformCode, 1).f32(kSrow + 16 + 12, kInf); }, {"srow_y[3]", "finite", "inf"}},
        {[](HeaderBytes& h) { h.i16(kSformCode, 1); }, {"srow_x/y/z", "invertible"}},  // all-zero rows
        {[kNan](HeaderBytes& h) { h.i16(kQformCode, 1).f32(kQuatern + 4, kNan); }, {"quatern_c", "finite"}},
        {[](HeaderBytes& h) { h.i16(kQformCode, 1).f32(kPixdim + 12, 0); }, {"pixdim[3]", "non-zero"}},
        {[](HeaderBytes& h) { h.i16(kSformCode, -1); }, {"sform_code", ">= 0"}},
    };
    for (const Case& c : cases) {
        HeaderBytes header = nifti_header();
        c.spoil(header);
        const std::string message = parse_error(header);
        ASSERT_FALSE(message.empty()) << c.parts[0];
        EXPECT_MESSAGE_HAS(message, "test.nii: ");
        for (const std::string& part : c.parts) EXPECT_MESSAGE_HAS(message, part);
    }
}

TEST(NiftiAnalyzeTest, ShortHeaderThrows) {
    const HeaderBytes header = nifti_header();
    EXPECT_THROW(detail::parse_nifti_analyze_header(header.bytes().data(), 200, "t.nii"), FormatError);
    test::ScratchDir dir;
    test::write_bytes(dir / "t.nii", Bytes(header.bytes().begin(), header.bytes().begin() + 100));
    EXPECT_MESSAGE_HAS(open_error(dir / "t.nii"), "header: expected 348 bytes, got 100 bytes");
}

TEST(NiftiAnalyzeTest, HeaderWithoutItsImageThrows) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.hdr", test::read_bytes(test::testdata("read/analyze_be_i16.hdr")));
    EXPECT_MESSAGE_HAS(open_error(dir / "a.hdr"), "image file: expected a.img or a.img.gz beside it");
    test::write_bytes(dir / "b.img", Bytes(48));
    EXPECT_MESSAGE_HAS(open_error(dir / "b.img"), "header file: expected b.hdr or b.hdr.gz beside it");
}

TEST(NiftiAnalyzeTest, GzippedImageOfAPairIsFound) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.hdr", test::read_bytes(test::testdata("read/analyze_be_i16.hdr")));
    test::write_bytes(dir / "a.img.gz", test::gzip_bytes(test::read_bytes(test::testdata("read/analyze_be_i16.img"))));
    const VolumeSource source = open_volume_source(dir / "a.hdr");
    ASSERT_EQ(source.segments.size(), 1u);
    EXPECT_EQ(source.segments[0].path.filename(), "a.img.gz");
    EXPECT_EQ(test::read_all(source)[0], -25.0f);  // 0.5 * (0 - 50)
}

TEST(NiftiAnalyzeTest, NiiWithoutTheSingleFileMagicThrows) {
    test::ScratchDir dir;
    HeaderBytes header = nifti_header();
    header.text(kMagic, std::string("ni1\0", 4)).f32(kVoxOffset, 0);
    test::write_bytes(dir / "t.nii", nii_file(header, Bytes(8)));
    EXPECT_MESSAGE_HAS(open_error(dir / "t.nii"), "magic: expected \"n+1\"");
}

TEST(NiftiAnalyzeTest, FileSizeMismatchThrowsBeforeReading) {
    test::ScratchDir dir;
    test::write_bytes(dir / "short.nii", nii_file(nifti_header(), Bytes(7)));
    EXPECT_THROW(open_volume_source(dir / "short.nii"), FormatError);
    EXPECT_MESSAGE_HAS(open_error(dir / "short.nii"), "file size: expected 360 bytes");
    test::write_bytes(dir / "long.nii", nii_file(nifti_header(), Bytes(9)));
    EXPECT_THROW(open_volume_source(dir / "long.nii"), FormatError);
    EXPECT_MESSAGE_HAS(open_error(dir / "long.nii"), "got 361 bytes");
}

TEST(NiftiAnalyzeTest, GzippedFileIsCheckedWhileStreaming) {
    test::ScratchDir dir;
    test::write_bytes(dir / "short.nii.gz", test::gzip_bytes(nii_file(nifti_header(), Bytes(7))));
    EXPECT_MESSAGE_HAS(open_error(dir / "short.nii.gz"), "truncated");
    test::write_bytes(dir / "long.nii.gz", test::gzip_bytes(nii_file(nifti_header(), Bytes(10))));
    const std::string message = open_error(dir / "long.nii.gz");
    EXPECT_MESSAGE_HAS(message, "trailing data");
    EXPECT_MESSAGE_HAS(message, "2 more bytes");
}

// Issue 10, point 6: zlib names a stream it was given by descriptor "<fd:3>", and its
// messages went out as they were: "got <fd:3>: incorrect data check".
TEST(NiftiAnalyzeTest, AGzipChecksumMismatchIsNamedWithoutZlibsStreamName) {
    test::ScratchDir dir;
    Bytes gzip = test::gzip_bytes(nii_file(nifti_header(), Bytes(8)));
    gzip[gzip.size() - 8] ^= 0xff;  // the CRC-32 of the trailer
    test::write_bytes(dir / "crc.nii.gz", gzip);
    const std::string message = open_error(dir / "crc.nii.gz");
    EXPECT_MESSAGE_HAS(message, (dir / "crc.nii.gz").string() + ": gzip stream: expected valid compressed data, got incorrect data check");
    EXPECT_EQ(message.find("<fd:"), std::string::npos) << message;
    // A larger file: the header is read from its start, the CRC found while streaming.
    std::ifstream in(test::testdata("sphere_phantom.nii.gz"), std::ios::binary);
    Bytes large((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(large.size(), 1000u);
    large[large.size() - 8] ^= 0xff;
    test::write_bytes(dir / "large.nii.gz", large);
    const std::string streamed = open_error(dir / "large.nii.gz");
    EXPECT_MESSAGE_HAS(streamed, (dir / "large.nii.gz").string() + ": gzip stream: expected valid compressed data, got incorrect data check");
    EXPECT_EQ(streamed.find("<fd:"), std::string::npos) << streamed;
}

TEST(NiftiAnalyzeTest, NanInFloatDataThrows) {
    test::ScratchDir dir;
    HeaderBytes header = nifti_header();
    header.i16(kDatatype, 16).i16(kBitpix, 32);
    std::vector<float> values(8, 2.0f);
    values[7] = std::numeric_limits<float>::quiet_NaN();
    Bytes samples(32);
    std::memcpy(samples.data(), values.data(), 32);
    test::write_bytes(dir / "t.nii", nii_file(header, samples));
    EXPECT_MESSAGE_HAS(open_error(dir / "t.nii"), "sample (1, 1, 1): expected a finite number, got NaN");
}

// ---------------------------------------------------------------- real scans

/// Min and max of every sample.
std::pair<float, float> min_max(const std::vector<float>& values) {
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    return {*lo, *hi};
}

TEST(NiftiAnalyzeTest, EngineCt) {
    VDBMESH_SHARED_DATA(path, "nifti_engine_ct/engine.nii.gz");
    const VolumeSource source = open_volume_source(path);
    const VolumeHeader& h = source.header;
    EXPECT_EQ(h.dims, (std::array<std::int64_t, 3>{256, 256, 128}));
    EXPECT_EQ(h.type, SampleType::u8);
    EXPECT_EQ(h.units, "mm");
    EXPECT_EQ(h.spacing, (std::array<double, 3>{1, 1, 1}));
    expect_affine_near(h.index_to_world, axis_aligned_affine({1, 1, 1}, {-127, -127, -64}), 0);
    const std::vector<float> values = test::read_all(source, 16);
    EXPECT_EQ(test::voxel(values, h, 128, 128, 64), 136.0f);
    EXPECT_EQ(test::voxel(values, h, 150, 100, 90), 139.0f);
    EXPECT_EQ(test::voxel(values, h, 60, 120, 40), 0.0f);
    EXPECT_EQ(min_max(values), std::make_pair(0.0f, 255.0f));
}

// srow_x/y/z of CT_pitch.nii.gz as float32 (python3 struct), the reference for both forms.
const Affine kPitchSrow{{{0.8125, 0.0, 0.0, -69.02075958251953},
                         {0.0, 0.779041051864624, 0.6807987689971924, -134.38560485839844},
                         {0.0, -0.23076248168945312, 2.2983384132385254, -13.56882095336914}}};

void expect_corners_match(const Affine& got, const VolumeHeader& h, double tolerance_mm) {
    for (int corner = 0; corner < 8; ++corner) {
        const double i = (corner & 1) ? h.dims[0] - 1 : 0, j = (corner & 2) ? h.dims[1] - 1 : 0,
                     k = (corner & 4) ? h.dims[2] - 1 : 0;
        const auto world = test::world_of(got, i, j, k), expected = test::world_of(kPitchSrow, i, j, k);
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(world[a], expected[a], tolerance_mm) << "corner " << corner;
    }
}

TEST(NiftiAnalyzeTest, ObliqueCtPitchCornersFromSformAndFromQform) {
    VDBMESH_SHARED_DATA(path, "nifti_ct_pitch_phantom/CT_pitch.nii.gz");
    const VolumeSource source = open_volume_source(path);
    const VolumeHeader& h = source.header;
    EXPECT_EQ(h.dims, (std::array<std::int64_t, 3>{175, 248, 58}));
    // The sform is used as stored: to 1e-3 mm (well below float rounding of the corners).
    expect_corners_match(h.index_to_world, h, 1e-3);
    EXPECT_NEAR(h.spacing[0], 0.8125, 1e-6);
    EXPECT_NEAR(h.spacing[1], 0.8125, 1e-5);
    EXPECT_NEAR(h.spacing[2], 2.3970494, 1e-5);
    // The same scan through its quaternion (sform_code cleared): the stored qform and sform
    // describe the same rotation, so the corners agree to 1e-3 mm too.
    std::vector<unsigned char> bytes = detail::read_prefix(path, detail::kNiftiHeaderBytes);
    bytes[kSformCode] = bytes[kSformCode + 1] = 0;
    const auto qform = detail::parse_nifti_analyze_header(bytes.data(), bytes.size(), path);
    expect_corners_match(qform.header.index_to_world, h, 1e-3);

    const std::vector<float> values = test::read_all(source, 7);
    EXPECT_EQ(test::voxel(values, h, 87, 124, 29), 156.0f);
    EXPECT_EQ(test::voxel(values, h, 60, 100, 20), 132.0f);
    EXPECT_EQ(test::voxel(values, h, 174, 247, 57), 0.0f);
}

TEST(NiftiAnalyzeTest, Seg3dMrAppliesSclSlope) {
    VDBMESH_SHARED_DATA(path, "nifti_seg3d_mr_t1/MR.nii.gz");
    const VolumeSource source = open_volume_source(path);
    const VolumeHeader& h = source.header;
    EXPECT_EQ(h.dims, (std::array<std::int64_t, 3>{160, 232, 160}));
    const double slope = 2.007843255996704;  // scl_slope as float32
    EXPECT_EQ(h.value_scale, slope);
    EXPECT_EQ(h.value_offset, 0);
    expect_affine_near(h.index_to_world,
                       axis_aligned_affine({1.0, 0.8984370231628418, 0.8984370231628418},
                                           {-388.260009765625, -81.11995697021484, 405.4209899902344}),
                       0);
    const std::vector<float> values = test::read_all(source, 32);
    EXPECT_FLOAT_EQ(test::voxel(values, h, 80, 116, 80), static_cast<float>(51 * slope));
    EXPECT_FLOAT_EQ(test::voxel(values, h, 40, 100, 60), static_cast<float>(151 * slope));
    EXPECT_FLOAT_EQ(min_max(values).second, static_cast<float>(255 * slope));
}

TEST(NiftiAnalyzeTest, Spm12XFlippedQfacMinusOne) {
    VDBMESH_SHARED_DATA(path, "nifti_spm12_single_subj_t1/single_subj_T1.nii");
    const VolumeSource source = open_volume_source(path);
    const Affine expected{{{-2, 0, 0, 90}, {0, 2, 0, -126}, {0, 0, 2, -72}}};
    expect_affine_near(source.header.index_to_world, expected, 0);
    EXPECT_EQ(source.header.spacing, (std::array<double, 3>{2, 2, 2}));
    // The qform alone (quaternion (0, 1, 0), qfac -1) gives the same matrix.
    std::vector<unsigned char> bytes = detail::read_prefix(path, detail::kNiftiHeaderBytes);
    bytes[kSformCode] = bytes[kSformCode + 1] = 0;
    expect_affine_near(detail::parse_nifti_analyze_header(bytes.data(), bytes.size(), path).header.index_to_world,
                       expected, 1e-6);
}

/// The inverse of an affine's 3x3 part (the tests' affines are well conditioned).
std::array<std::array<double, 3>, 3> inverse3(const Affine& m) {
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    std::array<std::array<double, 3>, 3> inv{};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
            inv[r][c] = (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det;
        }
    return inv;
}

TEST(NiftiAnalyzeTest, Spm2AnalyzeAndSpm12NiftiAgreeInWorldSpace) {
    VDBMESH_SHARED_DATA(analyze_path, "analyze_spm2_single_subj_t1/spm2_single_subj_T1.hdr");
    VDBMESH_SHARED_DATA(nifti_path, "nifti_spm12_single_subj_t1/single_subj_T1.nii");
    const VolumeSource analyze = open_volume_source(analyze_path), nifti = open_volume_source(nifti_path);
    const VolumeHeader &a = analyze.header, &n = nifti.header;
    EXPECT_EQ(a.byte_order, ByteOrder::big);
    EXPECT_EQ(a.dims, (std::array<std::int64_t, 3>{91, 109, 91}));
    EXPECT_EQ(a.value_scale, static_cast<double>(0.003921568859368563f));  // funused1
    EXPECT_EQ(a.units, "mm");
    const auto a0 = test::world_of(a.index_to_world, 0, 0, 0), n90 = test::world_of(n.index_to_world, 90, 0, 0);
    for (int axis = 0; axis < 3; ++axis) EXPECT_EQ(a0[axis], n90[axis]);
    EXPECT_EQ(a0, (std::array<double, 3>{-90, -126, -72}));

    const std::vector<float> va = test::read_all(analyze, 10), vn = test::read_all(nifti, 10);
    EXPECT_FLOAT_EQ(test::voxel(va, a, 45, 63, 36), 33 * 0.003921568859368563f);
    EXPECT_FLOAT_EQ(test::voxel(vn, n, 45, 63, 36), static_cast<float>(33 * 0.003906190162524581));
    // Pearson correlation of the two at every Analyze voxel centre, mapped to the NIfTI's
    // index through both affines (0.989 measured with python3 via the x flip).
    const auto inv = inverse3(n.index_to_world);
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, count = 0;
    for (std::int64_t k = 0; k < a.dims[2]; ++k)
        for (std::int64_t j = 0; j < a.dims[1]; ++j)
            for (std::int64_t i = 0; i < a.dims[0]; ++i) {
                const auto w = test::world_of(a.index_to_world, i, j, k);
                std::array<std::int64_t, 3> idx{};
                bool inside = true;
                for (int r = 0; r < 3; ++r) {
                    double v = 0;
                    for (int c = 0; c < 3; ++c) v += inv[r][c] * (w[c] - n.index_to_world[c][3]);
                    idx[r] = std::llround(v);
                    inside = inside && idx[r] >= 0 && idx[r] < n.dims[r];
                }
                if (!inside) continue;
                const double x = test::voxel(va, a, i, j, k), y = test::voxel(vn, n, idx[0], idx[1], idx[2]);
                sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y, count += 1;
            }
    EXPECT_EQ(count, 91.0 * 109 * 91);  // same grid
    const double r = (count * sxy - sx * sy) / std::sqrt((count * sxx - sx * sx) * (count * syy - sy * sy));
    EXPECT_GT(r, 0.95);
}

}  // namespace
}  // namespace vdbmesh
