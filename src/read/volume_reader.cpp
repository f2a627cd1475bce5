// Streams the samples of a VolumeSource slab by slab and decodes them to float.
//
// Each DataSegment (read.h) is opened with open() and lseek() to its file_offset, then read
// as plain bytes (Compression::none), or through zlib: gzdopen() + gzread() for Compression::detect (plain bytes pass through as
// they are, and concatenated gzip members read as one stream, RFC 1952 section 2.2), or
// inflate() for Compression::zlib (a zlib-wrapped deflate stream, RFC 1950, as in MetaImage
// CompressedData). The segment's offset is then skipped in the decompressed stream.
//
// The stream length is checked exactly: running out of bytes is "truncated"; bytes left in a
// segment after its samples, or anywhere after the last slice, are "trailing data" (unless the
// segment allows them: a 4-D image of which only the first volume is read).

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>

#include "formats.h"
#include "vdbmesh/error.h"
#include "vdbmesh/parse_util.h"
#include "vdbmesh/read.h"

namespace vdbmesh {

std::string detail::describe_sample_bytes(const VolumeHeader& h, std::size_t files) {
    const std::uint64_t bytes = static_cast<std::uint64_t>(h.voxel_count()) * sample_size(h.type);
    return std::to_string(bytes) + " bytes of samples (" + std::to_string(h.dims[0]) + " x " + std::to_string(h.dims[1]) + " x " +
           std::to_string(h.dims[2]) + " " + to_string(h.type) + ")" + (files > 1 ? " in " + std::to_string(files) + " files" : "");
}

namespace {

constexpr std::size_t kBufferBytes = std::size_t{1} << 18;
/// zlib counts in unsigned int: never ask for more per call.
constexpr std::size_t kMaxChunk = std::size_t{1} << 30;

/// The decompressed bytes of one segment, from its file_offset on.
class SegmentInput {
public:
    virtual ~SegmentInput() = default;
    /// Reads up to @a size bytes into @a out; returns 0 at the end of the stream.
    /// Throws FormatError on corrupt or cut-off compressed data.
    virtual std::size_t read(unsigned char* out, std::size_t size) = 0;
    /// Passes over up to @a size bytes as read() would; returns how many, 0 at the end.
    virtual std::size_t skip(std::size_t size) {
        scratch_.resize(std::min(size, kBufferBytes));
        return read(scratch_.data(), scratch_.size());
    }

private:
    std::vector<unsigned char> scratch_;
};

/// Plain or gzip bytes through gzread (transparent for data without the gzip magic).
class GzipInput final : public SegmentInput {
public:
    GzipInput(std::filesystem::path path, int fd)
        : path_(std::move(path)), stream_name_("<fd:" + std::to_string(fd) + ">"), file_(gzdopen(fd, "rb")) {
        if (!file_) {
            ::close(fd);
            throw Error(path_.string() + ": cannot start reading (out of memory)");
        }
        gzbuffer(file_, kBufferBytes);
    }
    ~GzipInput() override { gzclose(file_); }

    std::size_t read(unsigned char* out, std::size_t size) override {
        const int got = gzread(file_, out, static_cast<unsigned>(std::min(size, kMaxChunk)));
        if (got >= 0) return static_cast<std::size_t>(got);
        int status = Z_OK;
        const char* message = gzerror(file_, &status);
        if (status == Z_BUF_ERROR)
            throw FormatError(path_.string(), "gzip stream", "a complete gzip stream", "one cut short (truncated)");
        throw FormatError(path_.string(), "gzip stream", "valid compressed data", detail::gzip_error_reason(message, stream_name_));
    }

private:
    std::filesystem::path path_;
    std::string stream_name_;  ///< what zlib calls the stream in its messages
    gzFile file_;
};

/// Plain bytes, read as they are (even when they happen to start with the gzip magic).
class PlainInput final : public SegmentInput {
public:
    /// @a fd at @a offset of a file of @a size bytes.
    PlainInput(std::filesystem::path path, int fd, std::uint64_t offset, std::uint64_t size)
        : path_(std::move(path)), fd_(fd), position_(offset), size_(size) {}
    ~PlainInput() override { ::close(fd_); }

    std::size_t read(unsigned char* out, std::size_t size) override {
        const ssize_t got = ::read(fd_, out, std::min(size, kMaxChunk));
        if (got < 0) throw Error(path_.string() + ": read failed: " + std::strerror(errno));
        position_ += static_cast<std::uint64_t>(got);
        return static_cast<std::size_t>(got);
    }

    /// Seeks: a column of bricks reads only the rows of its part of each slice.
    std::size_t skip(std::size_t size) override {
        const std::uint64_t step = std::min<std::uint64_t>(size, size_ > position_ ? size_ - position_ : 0);
        if (step > 0 && ::lseek(fd_, static_cast<off_t>(step), SEEK_CUR) < 0)
            throw Error(path_.string() + ": seek failed: " + std::strerror(errno));
        position_ += step;
        return static_cast<std::size_t>(step);
    }

private:
    std::filesystem::path path_;
    int fd_;
    std::uint64_t position_, size_;
};

/// A zlib-wrapped deflate stream, inflated by hand; nothing may follow it in the file.
class ZlibInput final : public SegmentInput {
public:
    ZlibInput(std::filesystem::path path, int fd) : path_(std::move(path)), fd_(fd), in_(kBufferBytes) {
        if (inflateInit(&stream_) != Z_OK) {
            ::close(fd_);
            throw Error(path_.string() + ": cannot start inflating (out of memory)");
        }
    }
    ~ZlibInput() override {
        inflateEnd(&stream_);
        ::close(fd_);
    }

    std::size_t read(unsigned char* out, std::size_t size) override {
        if (ended_) {
            check_nothing_after();
            return 0;
        }
        const auto want = static_cast<unsigned>(std::min(size, kMaxChunk));
        stream_.next_out = out;
        stream_.avail_out = want;
        while (stream_.avail_out == want && !ended_) {
            if (stream_.avail_in == 0) refill();
            const int status = inflate(&stream_, Z_NO_FLUSH);
            if (status == Z_STREAM_END) ended_ = true;
            else if (status != Z_OK && status != Z_BUF_ERROR)
                throw FormatError(path_.string(), "zlib stream", "valid compressed data",
                                  stream_.msg ? stream_.msg : "corrupt data");
        }
        return want - stream_.avail_out;
    }

private:
    void refill() {
        const ssize_t got = ::read(fd_, in_.data(), in_.size());
        if (got < 0) throw Error(path_.string() + ": read failed: " + std::strerror(errno));
        if (got == 0)
            throw FormatError(path_.string(), "zlib stream", "a complete zlib stream", "one cut short (truncated)");
        stream_.next_in = in_.data();
        stream_.avail_in = static_cast<unsigned>(got);
    }

    void check_nothing_after() {
        std::uint64_t extra = stream_.avail_in;
        stream_.avail_in = 0;
        for (ssize_t got; (got = ::read(fd_, in_.data(), in_.size())) > 0;) extra += static_cast<std::uint64_t>(got);
        if (extra > 0)
            throw FormatError(path_.string(), "trailing data", "the file to end with the zlib stream",
                              std::to_string(extra) + " more bytes");
    }

    std::filesystem::path path_;
    int fd_;
    std::vector<unsigned char> in_;
    z_stream stream_{};
    bool ended_ = false;
};

/// Opens @a segment's file at its file_offset with the reader its compression needs.
std::unique_ptr<SegmentInput> open_input(const DataSegment& segment) {
    const std::string name = segment.path.string();
    const int fd = ::open(segment.path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw FormatError(name, "data file", "a readable file", std::strerror(errno));
    struct stat info {};
    if (::fstat(fd, &info) != 0 || segment.file_offset > static_cast<std::uint64_t>(info.st_size) ||
        segment.file_offset > static_cast<std::uint64_t>(LLONG_MAX) ||
        ::lseek(fd, static_cast<off_t>(segment.file_offset), SEEK_SET) < 0) {
        ::close(fd);
        throw FormatError(name, "data file offset", "at most the file size (" + std::to_string(info.st_size) + " bytes)",
                          std::to_string(segment.file_offset));
    }
    if (segment.compression == Compression::zlib) return std::make_unique<ZlibInput>(segment.path, fd);
    // Detected as plain (no gzip magic where the data starts) reads what gzread would read in
    // its transparent mode, and can seek.
    unsigned char magic[2] = {0, 0};
    const bool plain = segment.compression == Compression::none ||
                       ::pread(fd, magic, 2, static_cast<off_t>(segment.file_offset)) < 2 || magic[0] != 0x1f || magic[1] != 0x8b;
    if (plain) return std::make_unique<PlainInput>(segment.path, fd, segment.file_offset, static_cast<std::uint64_t>(info.st_size));
    return std::make_unique<GzipInput>(segment.path, fd);
}

/// Passes over the rest of @a input (at most @a limit bytes); returns how many bytes there were.
std::uint64_t count_rest(SegmentInput& input, std::uint64_t limit = ~std::uint64_t{0}) {
    std::uint64_t total = 0;
    while (total < limit) {
        const std::size_t got = input.skip(static_cast<std::size_t>(std::min<std::uint64_t>(kMaxChunk, limit - total)));
        if (got == 0) break;
        total += got;
    }
    return total;
}

}  // namespace

/// The samples of all segments as one byte stream of known total length.
class VolumeReader::ByteStream {
public:
    explicit ByteStream(const VolumeSource& source)
        : segments_(source.segments),
          total_bytes_(static_cast<std::uint64_t>(source.header.voxel_count()) * sample_size(source.header.type)),
          header_path_(source.header.path),
          expected_(detail::describe_sample_bytes(source.header, source.segments.size())) {}

    /// Fills @a out with exactly @a size bytes, or throws FormatError (truncated data).
    void read(unsigned char* out, std::size_t size) { advance(out, size); }
    /// Passes over exactly @a size bytes, or throws FormatError (truncated data).
    void skip(std::size_t size) { advance(nullptr, size); }

    /// After the last sample: throws FormatError "trailing data" when any stream holds more.
    void finish() {
        if (input_) close_segment();
        while (index_ < segments_.size()) {
            open_next();
            close_segment();
        }
    }

private:
    /// Reads @a size bytes into @a out, or passes over them when @a out is null.
    void advance(unsigned char* out, std::size_t size) {
        while (size > 0) {
            if (!input_) open_next();
            const DataSegment& segment = segments_[index_ - 1];
            const std::uint64_t left = segment.bytes == DataSegment::kToEnd ? size : segment.bytes - read_in_segment_;
            if (left == 0) {
                close_segment();
                continue;
            }
            const auto want = static_cast<std::size_t>(std::min<std::uint64_t>(size, left));
            const std::size_t got = out ? input_->read(out, want) : input_->skip(want);
            if (got == 0) {
                if (segment.bytes != DataSegment::kToEnd) throw_truncated_segment(segment);
                input_.reset();  // a kToEnd segment ends where its stream does
                continue;
            }
            if (out) out += got;
            size -= got;
            read_in_segment_ += got;
            read_total_ += got;
        }
    }

    void open_next() {
        if (index_ >= segments_.size()) throw_truncated_total();
        const DataSegment& segment = segments_[index_++];
        input_ = open_input(segment);
        read_in_segment_ = 0;
        const std::uint64_t skipped = count_rest(*input_, segment.offset);
        if (skipped < segment.offset)
            throw FormatError(segment.path.string(), "data offset",
                              "at least " + std::to_string(segment.offset) + " bytes before the samples",
                              "a stream of only " + std::to_string(skipped) + " bytes (truncated)");
    }

    /// Closes the open segment, checking that nothing follows its samples.
    void close_segment() {
        const DataSegment& segment = segments_[index_ - 1];
        if (!segment.allow_trailing) {
            const std::uint64_t extra = count_rest(*input_);
            if (extra > 0) throw_trailing(segment, extra);
        }
        input_.reset();
    }

    [[noreturn]] void throw_truncated_segment(const DataSegment& segment) const {
        throw FormatError(segment.path.string(), "sample data",
                          std::to_string(segment.bytes) + " bytes after offset " + std::to_string(segment.offset),
                          "only " + std::to_string(read_in_segment_) + " bytes (truncated)");
    }

    /// The streams together ended early: said as the plain raw's size check says it (raw.cpp),
    /// naming the one data file, or the header's file for several.
    [[noreturn]] void throw_truncated_total() const {
        const std::string file = segments_.size() == 1 ? segments_.front().path.string() : header_path_.string();
        throw FormatError(file, "sample data", expected_, "only " + std::to_string(read_total_) + " bytes (truncated)");
    }

    [[noreturn]] void throw_trailing(const DataSegment& segment, std::uint64_t extra) const {
        const std::string expected =
            segment.bytes == DataSegment::kToEnd
                ? std::to_string(total_bytes_) + " bytes of samples in all"
                : std::to_string(segment.bytes) + " bytes of samples after offset " + std::to_string(segment.offset);
        throw FormatError(segment.path.string(), "trailing data", expected, std::to_string(extra) + " more bytes");
    }

    std::vector<DataSegment> segments_;
    std::uint64_t total_bytes_;
    std::filesystem::path header_path_;
    std::string expected_;  ///< describe_sample_bytes()
    std::size_t index_ = 0;  ///< segments opened so far; the open one is index_ - 1
    std::unique_ptr<SegmentInput> input_;
    std::uint64_t read_in_segment_ = 0;
    std::uint64_t read_total_ = 0;
};

namespace {

/// Narrows to float; values beyond float range become infinities (a bare cast would be undefined).
float to_float(double value) {
    constexpr double kMax = std::numeric_limits<float>::max();
    if (value > kMax) return std::numeric_limits<float>::infinity();
    if (value < -kMax) return -std::numeric_limits<float>::infinity();
    return static_cast<float>(value);
}

template <typename T>
void decode_as(const unsigned char* bytes, std::size_t count, bool swap, double scale, double offset, float* out) {
    for (std::size_t i = 0; i < count; ++i) {
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, bytes + i * sizeof(T), sizeof(T));
        if (swap) std::reverse(raw, raw + sizeof(T));
        T value;
        std::memcpy(&value, raw, sizeof(T));
        out[i] = to_float(static_cast<double>(value) * scale + offset);
    }
}

void decode(const unsigned char* bytes, std::size_t count, SampleType type, bool swap, double scale, double offset,
            float* out) {
    visit_sample_type(type, [&](auto zero) { decode_as<decltype(zero)>(bytes, count, swap, scale, offset, out); });
}

bool host_is_little() {
    const std::uint16_t probe = 1;
    unsigned char first;
    std::memcpy(&first, &probe, 1);
    return first == 1;
}

/// Throws FormatError at the first NaN or infinity among @a values, the samples of @a part of
/// consecutive slices from @a first_slice: a float sample, or an integer one that the value
/// scale pushed out of float range.
void check_finite(const VolumeHeader& h, const SliceRectangle& part, const float* values, std::size_t count, std::int64_t first_slice) {
    const float* bad = std::find_if(values, values + count, [](float v) { return !std::isfinite(v); });
    if (bad == values + count) return;
    const std::int64_t index = bad - values;
    const std::int64_t x = part.min_x + index % part.width, y = part.min_y + (index / part.width) % part.height;
    const std::int64_t z = first_slice + index / part.voxels();
    throw FormatError(h.path.string(),
                      "sample (" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) + ")",
                      "a finite number", std::isnan(*bad) ? "NaN" : "infinity");
}

}  // namespace

VolumeReader::VolumeReader(VolumeSource source)
    : source_(std::move(source)),
      stream_(std::make_unique<ByteStream>(source_)) {}

VolumeReader::~VolumeReader() = default;

void VolumeReader::read_slices(std::int64_t slices, float* out) {
    const VolumeHeader& h = source_.header;
    if (slices < 0 || next_slice_ + slices > h.dims[2]) throw Error("internal: read_slices past the last slice");
    const std::size_t count = static_cast<std::size_t>(h.slice_voxels() * slices);
    buffer_.resize(count * sample_size(h.type));
    stream_->read(buffer_.data(), buffer_.size());
    const bool swap = (h.byte_order == ByteOrder::little) != host_is_little();
    decode(buffer_.data(), count, h.type, swap, h.value_scale, h.value_offset, out);
    check_finite(h, {0, 0, h.dims[0], h.dims[1]}, out, count, next_slice_);
    next_slice_ += slices;
    if (next_slice_ == h.dims[2]) stream_->finish();
}

void VolumeReader::read_slice_part(std::int64_t slices, const SliceRectangle& part, float* out) {
    const VolumeHeader& h = source_.header;
    if (slices < 0 || next_slice_ + slices > h.dims[2]) throw Error("internal: read_slice_part past the last slice");
    detail::check_slice_part(h, part);
    // The rows of the part are read whole, the rows around them passed over (a plain file
    // seeks; a compressed one decompresses them), and only the part's columns decoded.
    const auto row_bytes = static_cast<std::size_t>(h.dims[0]) * sample_size(h.type);
    buffer_.resize(static_cast<std::size_t>(part.height) * row_bytes);
    const bool swap = (h.byte_order == ByteOrder::little) != host_is_little();
    for (std::int64_t s = 0; s < slices; ++s) {
        stream_->skip(static_cast<std::size_t>(part.min_y) * row_bytes);
        stream_->read(buffer_.data(), buffer_.size());
        stream_->skip(static_cast<std::size_t>(h.dims[1] - part.min_y - part.height) * row_bytes);
        float* slice = out + static_cast<std::size_t>(s * part.voxels());
        for (std::int64_t y = 0; y < part.height; ++y) {
            const std::size_t first = static_cast<std::size_t>(y) * row_bytes + static_cast<std::size_t>(part.min_x) * sample_size(h.type);
            decode(buffer_.data() + first, static_cast<std::size_t>(part.width), h.type, swap, h.value_scale, h.value_offset,
                   slice + y * part.width);
        }
        check_finite(h, part, slice, static_cast<std::size_t>(part.voxels()), next_slice_);
        if (++next_slice_ == h.dims[2]) stream_->finish();
    }
}

std::unique_ptr<VolumeReader> open_volume(const std::filesystem::path& path, const ReadOptions& options) {
    return std::make_unique<VolumeReader>(open_volume_source(path, options));
}

}  // namespace vdbmesh
