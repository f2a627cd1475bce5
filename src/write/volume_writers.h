#pragma once
// Private: one writer per format (write_<format>.cpp), picked by write_volume.cpp, and the
// pieces they share (write_samples.cpp): a plain or gzip byte sink, the float -> stored
// sample encoder, the slice loop, fixed-layout binary headers and number formatting.

#include <zlib.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "vdbmesh/read.h"
#include "vdbmesh/write_volume.h"

namespace vdbmesh::detail {

// ---- the writers (each validates what its format can hold, then writes atomically) ----

/// A .nii (magic "n+1") when @a single_file, else a NIfTI pair .hdr + .img (magic "ni1") named
/// after @a path; the .nii, or the .img, gzip-compressed when @a gzip.
WriteResult write_nifti(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices,
                        bool single_file, bool gzip);
/// Analyze 7.5 pair .hdr + .img named after @a path (SPM scale in funused1, origin in originator).
WriteResult write_analyze(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices);
/// OpenQVis .dat + .raw (UCHAR, USHORT or FLOAT, little-endian).
WriteResult write_openqvis(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices);
/// MetaImage .mha with the samples after the header when @a attached, else .mhd + .raw.
WriteResult write_metaimage(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices,
                            bool attached);
/// NRRD .nrrd with the samples after the header when @a attached, else .nhdr + .raw (.raw.gz);
/// "encoding: gzip" when @a gzip, else raw.
WriteResult write_nrrd(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices,
                       bool attached, bool gzip);
/// Headerless samples, gzip-compressed when @a gzip (.raw.gz).
WriteResult write_raw(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices,
                      bool gzip);

// ---- shared pieces ----

/// Bytes to a file, plain or gzip-compressed (zlib gzwrite: the gzip header carries no time,
/// so the bytes are the same every run).
class ByteSink {
public:
    /// Opens @a path (a temporary file) for writing, or for appending when @a append; @a name
    /// is the user's path, for messages.
    ByteSink(const std::filesystem::path& path, const std::filesystem::path& name, bool gzip, bool append = false);
    ~ByteSink();
    ByteSink(const ByteSink&) = delete;
    ByteSink& operator=(const ByteSink&) = delete;

    void write(const void* data, std::size_t size);
    void write(const std::string& text) { write(text.data(), text.size()); }
    /// Flushes and closes; throws Error when anything failed (disk full ...).
    void close();

private:
    [[noreturn]] void fail(const char* what);
    gzFile file_ = nullptr;
    std::filesystem::path name_;
    std::string stream_name_;  ///< what zlib calls the stream in its messages: the path opened
};

/// Checks what every writer needs: dims > 0 whose byte count fits in 63 bits, a finite
/// non-zero value_scale and a finite value_offset. Throws Error naming @a path.
void check_volume_header(const std::filesystem::path& path, const VolumeHeader& header);

/// Throws Error unless header.type is one of @a allowed; @a format names the format.
void require_type(const std::filesystem::path& path, const VolumeHeader& header, const std::string& format,
                  const std::vector<SampleType>& allowed);
/// Stores @a count values as header.type in header.byte_order: (value - value_offset) /
/// value_scale, rounded to nearest and clamped to the type's range for integer types (NaN
/// stores 0).
void encode_samples(const VolumeHeader& header, const float* values, std::size_t count, unsigned char* out);

/// Asks @a slices for z = 0, 1, ... dims[2] - 1 and hands each slice, encoded as @a header
/// says (encode_samples()), to @a write with its z.
void for_each_encoded_slice(const VolumeHeader& header, const SliceSource& slices,
                            const std::function<void(std::int64_t z, const std::vector<unsigned char>& bytes)>& write);

/// Writes every slice, encoded, to @a sink.
void write_samples(ByteSink& sink, const VolumeHeader& header, const SliceSource& slices);

/// Writes @a header_bytes to @a header_path and the samples to @a data_path (gzip-compressed
/// when @a gzip_data), each through AtomicFile: samples first, then the header; the data file
/// is committed before the header, so a reader never finds a header without its data.
void write_detached(const std::filesystem::path& header_path, const std::string& header_bytes,
                    const std::filesystem::path& data_path, bool gzip_data, const VolumeHeader& header,
                    const SliceSource& slices);
/// Writes @a prefix then the samples to one file through AtomicFile, gzip-compressed when @a gzip.
void write_attached(const std::filesystem::path& path, const std::string& prefix, bool gzip,
                    const VolumeHeader& header, const SliceSource& slices);

/// A fixed-layout binary header (Analyze, NIfTI) filled field by field in one byte order.
class BinaryRecord {
public:
    BinaryRecord(std::size_t size, ByteOrder order) : bytes_(size, 0), order_(order) {}
    void put_i16(std::size_t offset, std::int16_t value) { put(offset, &value, sizeof value); }
    void put_i32(std::size_t offset, std::int32_t value) { put(offset, &value, sizeof value); }
    void put_f32(std::size_t offset, float value) { put(offset, &value, sizeof value); }
    /// Copies @a text (truncated to @a capacity bytes; the rest stays zero).
    void put_text(std::size_t offset, std::size_t capacity, const std::string& text);
    std::string bytes() const { return std::string(bytes_.begin(), bytes_.end()); }

private:
    void put(std::size_t offset, const void* value, std::size_t size);
    std::vector<unsigned char> bytes_;
    ByteOrder order_;
};

/// sizeof_hdr of Analyze 7.5 and NIfTI-1.
constexpr std::size_t kAnalyzeHeaderSize = 348;

/// The fields Analyze 7.5 and NIfTI-1 share (write_analyze.cpp): sizeof_hdr, regular, dim,
/// datatype, bitpix, pixdim[1..3], descrip, in header.byte_order. Throws Error when the
/// type has no Analyze/NIfTI code or a dim exceeds 32767.
BinaryRecord analyze_common_fields(const std::filesystem::path& path, const VolumeHeader& header);

/// The shortest text that reads back as exactly @a value ("0.5", "1e-05", "255").
std::string format_number(double value);

/// @a path with its last extension replaced by @a extension (".img" for "a.hdr").
std::filesystem::path sibling(const std::filesystem::path& path, const std::string& extension);

/// The spacing along each index axis, from the affine's column lengths.
std::array<double, 3> affine_spacing(const Affine& affine);

/// True when the affine has no rotation or shear (each column has one non-zero entry, on the diagonal).
bool is_axis_aligned(const Affine& affine);

}  // namespace vdbmesh::detail
