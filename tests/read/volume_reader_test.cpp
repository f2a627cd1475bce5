// The sample stream (VolumeReader and its ByteStream): every DataSegment field, plain, gzip
// and zlib data, exact-length checks, decoding of every sample type in both byte orders.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "binary_test_util.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/read.h"

namespace vdbmesh {
namespace {

using test::Bytes;

/// A 2x2x2 u8 volume whose samples come from @a segments.
VolumeSource u8_cube(std::vector<DataSegment> segments, std::int64_t side = 2) {
    VolumeSource source;
    source.header.format = "test";
    source.header.path = "cube";
    source.header.dims = {side, side, side};
    source.header.type = SampleType::u8;
    source.segments = std::move(segments);
    return source;
}

DataSegment segment(const std::filesystem::path& path, std::uint64_t bytes = DataSegment::kToEnd,
                    std::uint64_t offset = 0, std::uint64_t file_offset = 0) {
    DataSegment s;
    s.path = path;
    s.bytes = bytes;
    s.offset = offset;
    s.file_offset = file_offset;
    return s;
}

const Bytes kEight{10, 11, 12, 13, 14, 15, 16, 17};
const std::vector<float> kEightFloats{10, 11, 12, 13, 14, 15, 16, 17};

/// The FormatError message from reading @a source to the end, or "" when none is thrown.
std::string read_error(VolumeSource source) {
    try {
        test::read_all(std::move(source));
    } catch (const FormatError& e) {
        return e.what();
    }
    return "";
}

TEST(VolumeReaderTest, PlainSegmentSkipsItsOffset) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.bin", test::concat(test::text_bytes("0123456789"), kEight));
    EXPECT_EQ(test::read_all(u8_cube({segment(dir / "a.bin", 8, 10)})), kEightFloats);
}

TEST(VolumeReaderTest, SlicesComeOneAtATimeInOrder) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.bin", kEight);
    VolumeReader reader(u8_cube({segment(dir / "a.bin", 8)}));
    float slice[4];
    reader.read_slices(1, slice);
    EXPECT_EQ(reader.next_slice(), 1);
    EXPECT_EQ(slice[3], 13.0f);
    reader.read_slices(1, slice);
    EXPECT_EQ(reader.next_slice(), 2);
    EXPECT_EQ(slice[0], 14.0f);
    EXPECT_THROW(reader.read_slices(1, slice), Error);
}

TEST(VolumeReaderTest, GzipOffsetCountsDecompressedBytes) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.gz", test::gzip_bytes(test::concat(test::text_bytes("head"), kEight)));
    EXPECT_EQ(test::read_all(u8_cube({segment(dir / "a.gz", 8, 4)})), kEightFloats);
}

TEST(VolumeReaderTest, ConcatenatedGzipMembersReadAsOneStream) {
    test::ScratchDir dir;
    const Bytes first(kEight.begin(), kEight.begin() + 3), second(kEight.begin() + 3, kEight.end());
    test::write_bytes(dir / "a.gz", test::concat(test::gzip_bytes(first), test::gzip_bytes(second)));
    EXPECT_EQ(test::read_all(u8_cube({segment(dir / "a.gz")})), kEightFloats);
}

TEST(VolumeReaderTest, FileOffsetSkipsATextHeaderBeforeGzipData) {
    test::ScratchDir dir;
    const Bytes header = test::text_bytes("NRRD0004\ntype: uchar\n\n");
    test::write_bytes(dir / "a.nrrd", test::concat(header, test::gzip_bytes(test::concat(Bytes{99, 98}, kEight))));
    EXPECT_EQ(test::read_all(u8_cube({segment(dir / "a.nrrd", 8, 2, header.size())})), kEightFloats);
}

TEST(VolumeReaderTest, ZlibSegmentIsInflated) {
    test::ScratchDir dir;
    const Bytes header = test::text_bytes("CompressedData = True\nElementDataFile = LOCAL\n");
    test::write_bytes(dir / "a.mha", test::concat(header, test::zlib_bytes(kEight)));
    DataSegment s = segment(dir / "a.mha", 8, 0, header.size());
    s.compression = Compression::zlib;
    EXPECT_EQ(test::read_all(u8_cube({s}), 1), kEightFloats);
}

TEST(VolumeReaderTest, ZlibSegmentOfALargerVolumeSpansManyReads) {
    // 64^3 samples read 5 slices at a time: each slab resumes the same inflate stream.
    test::ScratchDir dir;
    Bytes data(64 * 64 * 64);
    for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<unsigned char>((i * 7919) % 251);
    test::write_bytes(dir / "a.zraw", test::zlib_bytes(data));
    DataSegment s = segment(dir / "a.zraw");
    s.compression = Compression::zlib;
    const std::vector<float> values = test::read_all(u8_cube({s}, 64), 5);
    ASSERT_EQ(values.size(), data.size());
    EXPECT_TRUE(std::equal(values.begin(), values.end(), data.begin()));
}

TEST(VolumeReaderTest, BytesAfterAZlibStreamAreTrailingData) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.zraw", test::concat(test::zlib_bytes(kEight), Bytes{1, 2, 3}));
    DataSegment s = segment(dir / "a.zraw");
    s.compression = Compression::zlib;
    const std::string message = read_error(u8_cube({s}));
    EXPECT_NE(message.find("trailing data"), std::string::npos) << message;
    EXPECT_NE(message.find("3 more bytes"), std::string::npos) << message;
}

TEST(VolumeReaderTest, CutZlibStreamIsTruncated) {
    test::ScratchDir dir;
    Bytes data(1000, 7);
    for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<unsigned char>(i * 31);
    Bytes compressed = test::zlib_bytes(data);
    compressed.resize(compressed.size() / 2);
    test::write_bytes(dir / "a.zraw", compressed);
    DataSegment s = segment(dir / "a.zraw");
    s.compression = Compression::zlib;
    const std::string message = read_error(u8_cube({s}, 10));
    EXPECT_NE(message.find("truncated"), std::string::npos) << message;
}

TEST(VolumeReaderTest, CorruptZlibStreamThrows) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.zraw", Bytes{0x78, 0x9c, 0xff, 0xff, 0xff, 0xff, 0xff});
    DataSegment s = segment(dir / "a.zraw");
    s.compression = Compression::zlib;
    const std::string message = read_error(u8_cube({s}));
    EXPECT_NE(message.find("zlib stream"), std::string::npos) << message;
}

TEST(VolumeReaderTest, ToEndSegmentsJoinAcrossFilesIncludingEmptyOnes) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a", Bytes(kEight.begin(), kEight.begin() + 3));
    test::write_bytes(dir / "b", Bytes{});
    test::write_bytes(dir / "c.gz", test::gzip_bytes(Bytes(kEight.begin() + 3, kEight.end())));
    EXPECT_EQ(test::read_all(u8_cube({segment(dir / "a"), segment(dir / "b"), segment(dir / "c.gz")}), 1),
              kEightFloats);
}

TEST(VolumeReaderTest, KnownSizeSegmentsSplitTheStream) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a", test::concat(Bytes{0, 0}, Bytes(kEight.begin(), kEight.begin() + 5)));
    test::write_bytes(dir / "b", Bytes(kEight.begin() + 5, kEight.end()));
    EXPECT_EQ(test::read_all(u8_cube({segment(dir / "a", 5, 2), segment(dir / "b", 3)}), 2), kEightFloats);
}

TEST(VolumeReaderTest, ShortToEndStreamIsTruncated) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a", Bytes(kEight.begin(), kEight.begin() + 7));
    const std::string message = read_error(u8_cube({segment(dir / "a")}));
    EXPECT_NE(message.find("truncated"), std::string::npos) << message;
    EXPECT_NE(message.find("expected 8 bytes of samples (2 x 2 x 2 u8)"), std::string::npos) << message;
    EXPECT_NE(message.find("only 7"), std::string::npos) << message;
}

TEST(VolumeReaderTest, ShortKnownSizeSegmentIsTruncated) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.gz", test::gzip_bytes(Bytes(kEight.begin(), kEight.begin() + 6)));
    const std::string message = read_error(u8_cube({segment(dir / "a.gz", 8)}));
    EXPECT_NE(message.find("a.gz"), std::string::npos) << message;
    EXPECT_NE(message.find("only 6 bytes (truncated)"), std::string::npos) << message;
}

TEST(VolumeReaderTest, StreamShorterThanItsOffsetThrows) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a", Bytes{1, 2, 3});
    const std::string message = read_error(u8_cube({segment(dir / "a", 8, 100)}));
    EXPECT_NE(message.find("data offset"), std::string::npos) << message;
}

TEST(VolumeReaderTest, FileOffsetPastTheEndThrows) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a", kEight);
    const std::string message = read_error(u8_cube({segment(dir / "a", 8, 0, 9)}));
    EXPECT_NE(message.find("data file offset"), std::string::npos) << message;
}

TEST(VolumeReaderTest, MissingFileThrowsFormatError) {
    test::ScratchDir dir;
    const std::string message = read_error(u8_cube({segment(dir / "nothing")}));
    EXPECT_NE(message.find("nothing"), std::string::npos) << message;
}

// Issue 10, point 6: a FIFO was "missing", and a FIFO .nii without a writer hung the reader.
TEST(VolumeReaderTest, AFifoIsRefusedWithoutBeingOpened) {
    test::ScratchDir dir;
    for (const char* name : {"scan.nii", "scan.raw"}) {
        const auto fifo = dir / name;
        ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
        ReadOptions options;
        if (std::string(name) == "scan.raw") options.raw_dims = std::array<std::int64_t, 3>{2, 2, 2};
        try {
            open_volume(fifo, options);
            ADD_FAILURE() << name << ": opened";
        } catch (const FormatError& e) {
            EXPECT_NE(std::string(e.what()).find("FIFO"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("regular file"), std::string::npos) << e.what();
        }
    }
}

TEST(VolumeReaderTest, BytesAfterAKnownSizeSegmentAreTrailingData) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a.gz", test::gzip_bytes(test::concat(kEight, Bytes{0, 0})));
    const std::string message = read_error(u8_cube({segment(dir / "a.gz", 8)}));
    EXPECT_NE(message.find("trailing data"), std::string::npos) << message;
    EXPECT_NE(message.find("expected 8 bytes of samples"), std::string::npos) << message;
    EXPECT_NE(message.find("2 more bytes"), std::string::npos) << message;
}

TEST(VolumeReaderTest, BytesAfterTheLastToEndSegmentAreTrailingData) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a", Bytes(kEight.begin(), kEight.begin() + 4));
    test::write_bytes(dir / "b.gz", test::gzip_bytes(test::concat(Bytes(kEight.begin() + 4, kEight.end()), Bytes{1})));
    const std::string message = read_error(u8_cube({segment(dir / "a"), segment(dir / "b.gz")}));
    EXPECT_NE(message.find("b.gz: trailing data"), std::string::npos) << message;
    EXPECT_NE(message.find("1 more bytes"), std::string::npos) << message;
}

TEST(VolumeReaderTest, UnreadSegmentWithDataIsTrailingData) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a", kEight);
    test::write_bytes(dir / "b", Bytes{5});
    test::write_bytes(dir / "empty", Bytes{});
    EXPECT_EQ(test::read_all(u8_cube({segment(dir / "a"), segment(dir / "empty")})), kEightFloats);
    const std::string message = read_error(u8_cube({segment(dir / "a"), segment(dir / "b")}));
    EXPECT_NE(message.find("trailing data"), std::string::npos) << message;
}

TEST(VolumeReaderTest, AllowTrailingReadsOnlyTheFirstBytes) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a", test::concat(kEight, Bytes(16, 1)));
    DataSegment s = segment(dir / "a", 8);
    s.allow_trailing = true;
    EXPECT_EQ(test::read_all(u8_cube({s})), kEightFloats);
}

TEST(VolumeReaderTest, CorruptGzipThrowsFormatError) {
    test::ScratchDir dir;
    Bytes gz = test::gzip_bytes(Bytes(200, 42));
    for (std::size_t i = 10; i < gz.size() - 8; ++i) gz[i] = 0xff;
    test::write_bytes(dir / "a.gz", gz);
    const std::string message = read_error(u8_cube({segment(dir / "a.gz")}, 5));
    EXPECT_NE(message.find("gzip stream"), std::string::npos) << message;
}

TEST(VolumeReaderTest, CutGzipStreamIsTruncated) {
    test::ScratchDir dir;
    Bytes data(4000);
    for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<unsigned char>((i * i) % 253);
    Bytes gz = test::gzip_bytes(data);
    gz.resize(gz.size() / 2);
    test::write_bytes(dir / "a.gz", gz);
    const std::string message = read_error(u8_cube({segment(dir / "a.gz")}, 15));
    EXPECT_NE(message.find("truncated"), std::string::npos) << message;
}

TEST(VolumeReaderTest, ValueScaleAndOffsetApply) {
    test::ScratchDir dir;
    test::write_bytes(dir / "a", kEight);
    VolumeSource source = u8_cube({segment(dir / "a")});
    source.header.value_scale = 0.5;
    source.header.value_offset = -3;
    const std::vector<float> values = test::read_all(std::move(source));
    EXPECT_EQ(values.front(), 2.0f);  // 10 * 0.5 - 3
    EXPECT_EQ(values.back(), 5.5f);   // 17 * 0.5 - 3
}

template <typename T>
Bytes encode(const std::vector<T>& values, ByteOrder order) {
    Bytes out;
    for (T v : values) {
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, &v, sizeof(T));
        const std::uint16_t probe = 1;
        const bool host_little = *reinterpret_cast<const unsigned char*>(&probe) == 1;
        if ((order == ByteOrder::little) != host_little) std::reverse(raw, raw + sizeof(T));
        out.insert(out.end(), raw, raw + sizeof(T));
    }
    return out;
}

template <typename T>
void expect_decodes(SampleType type, const std::vector<T>& values) {
    for (ByteOrder order : {ByteOrder::little, ByteOrder::big}) {
        test::ScratchDir dir;
        test::write_bytes(dir / "a", encode(values, order));
        VolumeSource source = u8_cube({segment(dir / "a")});
        source.header.type = type;
        source.header.byte_order = order;
        const std::vector<float> got = test::read_all(std::move(source));
        for (std::size_t i = 0; i < values.size(); ++i)
            EXPECT_EQ(got[i], static_cast<float>(values[i])) << to_string(type) << " " << to_string(order) << " #" << i;
    }
}

TEST(VolumeReaderTest, DecodesEveryTypeInBothByteOrders) {
    expect_decodes<std::uint8_t>(SampleType::u8, {0, 1, 2, 127, 128, 200, 254, 255});
    expect_decodes<std::int8_t>(SampleType::i8, {-128, -1, 0, 1, 2, 3, 100, 127});
    expect_decodes<std::uint16_t>(SampleType::u16, {0, 1, 255, 256, 1000, 32768, 63536, 65535});
    expect_decodes<std::int16_t>(SampleType::i16, {-32768, -2000, -1, 0, 1, 256, 3272, 32767});
    expect_decodes<std::uint32_t>(SampleType::u32, {0, 1, 65536, 16777216, 100000, 7, 8, 4000000000u});
    expect_decodes<std::int32_t>(SampleType::i32, {-2147483647 - 1, -65536, -1, 0, 1, 65536, 12345678, 2147483647});
    expect_decodes<float>(SampleType::f32, {-1.5f, 0.0f, 1e-30f, 3.25f, 1e30f, -7.0f, 0.125f, 65504.0f});
    expect_decodes<double>(SampleType::f64, {-1.5, 0.0, 1e-300, 3.25, 1e30, -7.0, 0.125, 1.0 / 3.0});
}

TEST(VolumeReaderTest, NanOrInfinityInFloatDataThrows) {
    for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        test::ScratchDir dir;
        std::vector<float> values(8, 1.0f);
        values[5] = bad;  // voxel (1, 0, 1)
        test::write_bytes(dir / "a", encode(values, ByteOrder::little));
        VolumeSource source = u8_cube({segment(dir / "a")});
        source.header.type = SampleType::f32;
        const std::string message = read_error(std::move(source));
        EXPECT_NE(message.find("sample (1, 0, 1)"), std::string::npos) << message;
        EXPECT_NE(message.find(std::isnan(bad) ? "NaN" : "infinity"), std::string::npos) << message;
    }
}

TEST(VolumeReaderTest, DoubleOutOfFloatRangeThrows) {
    test::ScratchDir dir;
    std::vector<double> values(8, 1.0);
    values[2] = 1e300;
    test::write_bytes(dir / "a", encode(values, ByteOrder::little));
    VolumeSource source = u8_cube({segment(dir / "a")});
    source.header.type = SampleType::f64;
    const std::string message = read_error(std::move(source));
    EXPECT_NE(message.find("sample (0, 1, 0)"), std::string::npos) << message;
}

/// A 5 x 4 x 3 volume of big-endian i16 samples (sample i is 3 i - 40) read with a value scale,
/// its file plain or gzip (@a path's extension ".gz").
VolumeSource i16_volume(const std::filesystem::path& path) {
    Bytes bytes;
    for (int i = 0; i < 60; ++i) {
        const auto value = static_cast<std::uint16_t>(static_cast<std::int16_t>(3 * i - 40));
        bytes.push_back(static_cast<unsigned char>(value >> 8));
        bytes.push_back(static_cast<unsigned char>(value & 0xff));
    }
    test::write_bytes(path, path.extension() == ".gz" ? test::gzip_bytes(bytes) : bytes);
    VolumeSource source;
    source.header.format = "test";
    source.header.path = path;
    source.header.dims = {5, 4, 3};
    source.header.type = SampleType::i16;
    source.header.byte_order = ByteOrder::big;
    source.header.value_scale = 0.5;
    source.header.value_offset = 1;
    source.segments = {segment(path)};  // Compression::detect
    return source;
}

/// @a part of every slice of @a whole (read_all()'s samples of a volume @a dims across).
std::vector<float> crop(const std::vector<float>& whole, const std::array<std::int64_t, 3>& dims, const SliceRectangle& part) {
    std::vector<float> out;
    for (std::int64_t z = 0; z < dims[2]; ++z)
        for (std::int64_t y = part.min_y; y < part.min_y + part.height; ++y)
            for (std::int64_t x = part.min_x; x < part.min_x + part.width; ++x) out.push_back(whole[(z * dims[1] + y) * dims[0] + x]);
    return out;
}

/// Reads every slice's @a part with read_slice_part(), two slices then one.
std::vector<float> read_parts(SliceReader& reader, const SliceRectangle& part) {
    std::vector<float> out(static_cast<std::size_t>(part.voxels() * 3));
    reader.read_slice_part(2, part, out.data());
    EXPECT_EQ(reader.next_slice(), 2);
    reader.read_slice_part(1, part, out.data() + 2 * part.voxels());
    return out;
}

/// A reader that has only read_slices(): it uses SliceReader's default read_slice_part().
class WholeSlicesOnly final : public SliceReader {
public:
    explicit WholeSlicesOnly(VolumeSource source) : reader_(std::move(source)) {}
    const VolumeHeader& header() const override { return reader_.header(); }
    void read_slices(std::int64_t slices, float* out) override { reader_.read_slices(slices, out); }
    std::int64_t next_slice() const override { return reader_.next_slice(); }

private:
    VolumeReader reader_;
};

TEST(VolumeReaderTest, SlicePartsAreTheirPartsOfTheWholeSlices) {
    test::ScratchDir dir;
    const std::vector<float> whole = test::read_all(i16_volume(dir / "v.raw"));
    ASSERT_EQ(whole[7], 0.5f * (3 * 7 - 40) + 1);
    // The rows around a part are passed over by seeking (plain) or by decompressing (gzip).
    for (const SliceRectangle& part : {SliceRectangle{0, 0, 5, 4}, SliceRectangle{1, 2, 3, 2}, SliceRectangle{4, 0, 1, 4}})
        for (const char* name : {"v.raw", "v.raw.gz"}) {
            SCOPED_TRACE(name);
            VolumeReader reader(i16_volume(dir / name));
            EXPECT_EQ(read_parts(reader, part), crop(whole, {5, 4, 3}, part));
            WholeSlicesOnly plain(i16_volume(dir / name));
            EXPECT_EQ(read_parts(plain, part), crop(whole, {5, 4, 3}, part));
        }
    VolumeReader reader(i16_volume(dir / "v.raw"));
    std::vector<float> out(64);
    EXPECT_THROW(reader.read_slice_part(1, SliceRectangle{3, 0, 3, 1}, out.data()), Error);  // wider than the slice
}

TEST(VolumeReaderTest, SlicePartsCheckOnlyTheirSamplesAndNameTheScansVoxel) {
    test::ScratchDir dir;
    std::vector<float> values(3 * 3 * 2, 1.0f);
    values[0] = std::numeric_limits<float>::quiet_NaN();              // (0, 0, 0): outside the part
    values[9 + 3 * 2 + 2] = std::numeric_limits<float>::infinity();   // (2, 2, 1): inside it
    Bytes bytes(values.size() * sizeof(float));
    std::memcpy(bytes.data(), values.data(), bytes.size());
    test::write_bytes(dir / "f.raw", bytes);
    VolumeSource source;
    source.header.format = "test";
    source.header.path = dir / "f.raw";
    source.header.dims = {3, 3, 2};
    source.header.type = SampleType::f32;
    source.segments = {segment(dir / "f.raw")};
    VolumeReader reader(source);
    std::vector<float> out(4);
    reader.read_slice_part(1, SliceRectangle{1, 1, 2, 2}, out.data());
    EXPECT_EQ(out, std::vector<float>(4, 1.0f));
    try {
        reader.read_slice_part(1, SliceRectangle{1, 1, 2, 2}, out.data());
        ADD_FAILURE() << "no error for an infinite sample";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("sample (2, 2, 1)"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace vdbmesh
