#pragma once
/// @file read.h
/// @brief Reading scans: one interface for every format, a header first, then the
/// samples slab by slab, so memory never holds the dense volume.

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vdbmesh {

enum class SampleType { u8, i8, u16, i16, u32, i32, f32, f64 };
enum class ByteOrder { little, big };

/// Bytes per sample of @a type.
std::size_t sample_size(SampleType type);
/// "u8", "i16", "f32" ...
std::string to_string(SampleType type);
/// "little" or "big".
std::string to_string(ByteOrder order);
/// Parses "u8|i8|u16|i16|u32|i32|f32|f64"; throws UsageError otherwise.
SampleType parse_sample_type(const std::string& name);

/// Calls @a f with a zero of the C++ type that stores @a type (std::uint8_t ... double), so
/// that a template runs once per sample type:
/// `visit_sample_type(type, [&](auto zero) { decode<decltype(zero)>(...); })`.
template <class F>
void visit_sample_type(SampleType type, F&& f) {
    switch (type) {
        case SampleType::u8: return f(std::uint8_t{});
        case SampleType::i8: return f(std::int8_t{});
        case SampleType::u16: return f(std::uint16_t{});
        case SampleType::i16: return f(std::int16_t{});
        case SampleType::u32: return f(std::uint32_t{});
        case SampleType::i32: return f(std::int32_t{});
        case SampleType::f32: return f(float{});
        case SampleType::f64: return f(double{});
    }
}

/// 3x4 affine matrix, row major: world = m * (i, j, k, 1), with (i, j, k) a voxel index.
using Affine = std::array<std::array<double, 4>, 3>;

/// The affine of an axis-aligned grid with the given spacing and origin.
Affine axis_aligned_affine(const std::array<double, 3>& spacing, const std::array<double, 3>& origin = {0, 0, 0});

/// What a scan's header says. Sample values are raw * value_scale + value_offset.
struct VolumeHeader {
    std::string format;                  ///< "nifti", "analyze", "openqvis", "metaimage", "nrrd", "raw", "dicom", "vdb"
    std::filesystem::path path;          ///< the file (or DICOM folder) given by the user
    std::array<std::int64_t, 3> dims{};  ///< samples along x (fastest), y, z
    SampleType type = SampleType::u8;
    ByteOrder byte_order = ByteOrder::little;
    std::array<double, 3> spacing{1, 1, 1};  ///< world units per voxel along i, j, k (always positive)
    Affine index_to_world = axis_aligned_affine({1, 1, 1});
    double value_scale = 1.0;
    double value_offset = 0.0;
    std::string units;                   ///< "mm", "um", ... or empty when the file does not say
    std::vector<std::string> warnings;   ///< things a user should know (e.g. "no byte order key, assumed little")

    std::int64_t voxel_count() const { return dims[0] * dims[1] * dims[2]; }
    std::int64_t slice_voxels() const { return dims[0] * dims[1]; }
};

/// How a segment's bytes are stored.
enum class Compression {
    none,    ///< plain bytes, whatever they start with (formats that say their data is uncompressed)
    detect,  ///< gzip (one or more members) when the stream starts with the gzip magic, else plain
    zlib,    ///< zlib-wrapped deflate (MetaImage CompressedData)
};

/// One piece of the sample stream. Segments are read in order, each from its file:
/// skip file_offset bytes of the file, decompress from there, skip offset bytes of the
/// decompressed stream, then take @a bytes bytes (or everything up to the end).
/// Each stream must end with its samples (else FormatError "trailing data"), and together
/// the segments must hold exactly dims x sample size bytes (else "truncated" or "trailing data").
struct DataSegment {
    static constexpr std::uint64_t kToEnd = ~std::uint64_t{0};
    std::filesystem::path path;
    std::uint64_t file_offset = 0;  ///< bytes of the file before the (possibly compressed) stream
    std::uint64_t offset = 0;       ///< bytes to skip in the decompressed stream (a .nii.gz header)
    std::uint64_t bytes = kToEnd;   ///< sample bytes of this segment, or kToEnd: the rest of the stream
    Compression compression = Compression::detect;
    bool allow_trailing = false;    ///< true: the stream may go on after @a bytes (later volumes of a 4-D image)
};

/// A parsed header plus where its samples are.
struct VolumeSource {
    VolumeHeader header;
    std::vector<DataSegment> segments;
};

/// Options for headerless raw files (and overrides for every format).
struct ReadOptions {
    std::optional<std::array<std::int64_t, 3>> raw_dims;   ///< --raw-dims X,Y,Z: read the file as headerless raw
    SampleType raw_type = SampleType::u8;                  ///< --raw-type
    ByteOrder raw_byte_order = ByteOrder::little;           ///< --raw-endian
    std::array<double, 3> raw_spacing{1, 1, 1};             ///< --spacing
    std::uint64_t raw_header_bytes = 0;                     ///< --header-bytes
    std::vector<std::filesystem::path> raw_more_files;      ///< further parts, read after the first (a split scan)
    /// --allow-outside-data: read a data file that a header names outside the header's folder
    /// (refused by default: a header from elsewhere must not make us read any file it likes).
    bool allow_outside_data = false;
};

/// A rectangle of every z-slice: columns [min_x, min_x + width), rows [min_y, min_y + height).
struct SliceRectangle {
    std::int64_t min_x = 0, min_y = 0, width = 0, height = 0;
    std::int64_t voxels() const { return width * height; }
};

/// Samples of a volume handed out z-slice by z-slice as floats (what convert_to_grid()
/// consumes): a scan on disk (VolumeReader) or an array in memory (the Python module).
class SliceReader {
public:
    virtual ~SliceReader() = default;
    virtual const VolumeHeader& header() const = 0;
    /// Reads the next @a slices z-slices into @a out, which holds slice_voxels() * slices
    /// floats (x fastest). Throws FormatError on truncated data or a NaN/infinite sample.
    virtual void read_slices(std::int64_t slices, float* out) = 0;
    /// Reads the next @a slices z-slices keeping only @a part of each (which lies in the slice)
    /// into @a out, which holds part.voxels() * slices floats (x fastest): what a scan read by
    /// region needs of a column of bricks. The samples outside @a part need not be decoded nor
    /// checked. This default reads whole slices, one at a time, and copies the part.
    virtual void read_slice_part(std::int64_t slices, const SliceRectangle& part, float* out);
    /// Index of the next slice read_slices() returns.
    virtual std::int64_t next_slice() const = 0;
};

/// Streams the samples of a volume, slab by slab, as floats with the value scale applied.
class VolumeReader : public SliceReader {
public:
    explicit VolumeReader(VolumeSource source);
    ~VolumeReader() override;
    VolumeReader(const VolumeReader&) = delete;
    VolumeReader& operator=(const VolumeReader&) = delete;

    const VolumeHeader& header() const override { return source_.header; }
    /// Where the samples are read from (the files a header names, in order).
    const std::vector<DataSegment>& segments() const { return source_.segments; }
    void read_slices(std::int64_t slices, float* out) override;
    void read_slice_part(std::int64_t slices, const SliceRectangle& part, float* out) override;
    std::int64_t next_slice() const override { return next_slice_; }

private:
    class ByteStream;
    VolumeSource source_;
    std::unique_ptr<ByteStream> stream_;
    std::int64_t next_slice_ = 0;
    std::vector<unsigned char> buffer_;
};

/// Recognises the format of @a path (by extension, then by content) and parses its header.
/// A folder is read as a DICOM series. Throws FormatError on bad input.
VolumeSource open_volume_source(const std::filesystem::path& path, const ReadOptions& options = {});

/// open_volume_source() wrapped in a reader.
std::unique_ptr<VolumeReader> open_volume(const std::filesystem::path& path, const ReadOptions& options = {});

}  // namespace vdbmesh
