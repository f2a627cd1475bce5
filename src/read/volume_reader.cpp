// Streams the samples of a VolumeSource: its segments are read in order through zlib
// (which reads plain files as they are and concatenated gzip members as one stream),
// and decoded to float with the header's byte order and value scale.

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "parse_util.h"
#include "vdbmesh/error.h"
#include "vdbmesh/read.h"

namespace vdbmesh {

class VolumeReader::ByteStream {
public:
    explicit ByteStream(std::vector<DataSegment> segments) : segments_(std::move(segments)) {}
    ~ByteStream() { close(); }

    /// Fills @a out with exactly @a size bytes or throws FormatError (truncated data).
    void read(unsigned char* out, std::size_t size) {
        while (size > 0) {
            if (!file_ || left_in_segment_ == 0) open_next();
            const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>({size, left_in_segment_, 1u << 30}));
            const int got = gzread(file_, out, static_cast<unsigned>(want));
            if (got <= 0) throw_truncated();
            out += got;
            size -= static_cast<std::size_t>(got);
            left_in_segment_ -= static_cast<std::uint64_t>(got);
        }
    }

private:
    void open_next() {
        close();
        if (index_ >= segments_.size())
            throw Error("internal: read past the last data segment");
        const DataSegment& segment = segments_[index_++];
        detail::check_segment_size(segment);
        file_ = gzopen(segment.path.c_str(), "rb");
        if (!file_) throw FormatError(segment.path.string(), "cannot open the data file");
        gzbuffer(file_, 1 << 18);
        if (segment.offset > 0 && gzseek(file_, static_cast<z_off_t>(segment.offset), SEEK_SET) !=
                                      static_cast<z_off_t>(segment.offset))
            throw FormatError(segment.path.string(), "data offset", "at least " + std::to_string(segment.offset) + " bytes",
                              "a shorter file");
        left_in_segment_ = segment.bytes;
        read_in_segment_start_ = segment.bytes;
    }

    [[noreturn]] void throw_truncated() {
        const DataSegment& segment = segments_[index_ - 1];
        const std::uint64_t got = read_in_segment_start_ - left_in_segment_;
        throw FormatError(segment.path.string(), "sample data",
                          std::to_string(segment.bytes) + " bytes after offset " + std::to_string(segment.offset),
                          "only " + std::to_string(got) + " (truncated or corrupt)");
    }

    void close() {
        if (file_) gzclose(file_);
        file_ = nullptr;
    }

    std::vector<DataSegment> segments_;
    std::size_t index_ = 0;
    gzFile file_ = nullptr;
    std::uint64_t left_in_segment_ = 0;
    std::uint64_t read_in_segment_start_ = 0;
};

namespace {

template <typename T>
void decode_as(const unsigned char* bytes, std::size_t count, bool swap, double scale, double offset, float* out) {
    for (std::size_t i = 0; i < count; ++i) {
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, bytes + i * sizeof(T), sizeof(T));
        if (swap) std::reverse(raw, raw + sizeof(T));
        T value;
        std::memcpy(&value, raw, sizeof(T));
        out[i] = static_cast<float>(static_cast<double>(value) * scale + offset);
    }
}

void decode(const unsigned char* bytes, std::size_t count, SampleType type, bool swap, double scale, double offset,
            float* out) {
    switch (type) {
        case SampleType::u8: return decode_as<std::uint8_t>(bytes, count, swap, scale, offset, out);
        case SampleType::i8: return decode_as<std::int8_t>(bytes, count, swap, scale, offset, out);
        case SampleType::u16: return decode_as<std::uint16_t>(bytes, count, swap, scale, offset, out);
        case SampleType::i16: return decode_as<std::int16_t>(bytes, count, swap, scale, offset, out);
        case SampleType::u32: return decode_as<std::uint32_t>(bytes, count, swap, scale, offset, out);
        case SampleType::i32: return decode_as<std::int32_t>(bytes, count, swap, scale, offset, out);
        case SampleType::f32: return decode_as<float>(bytes, count, swap, scale, offset, out);
        case SampleType::f64: return decode_as<double>(bytes, count, swap, scale, offset, out);
    }
}

bool host_is_little() {
    const std::uint16_t probe = 1;
    unsigned char first;
    std::memcpy(&first, &probe, 1);
    return first == 1;
}

}  // namespace

VolumeReader::VolumeReader(VolumeSource source)
    : source_(std::move(source)), stream_(std::make_unique<ByteStream>(source_.segments)) {}

VolumeReader::~VolumeReader() = default;

void VolumeReader::read_slices(std::int64_t slices, float* out) {
    const VolumeHeader& h = source_.header;
    if (slices < 0 || next_slice_ + slices > h.dims[2])
        throw Error("internal: read_slices past the last slice");
    const std::size_t count = static_cast<std::size_t>(h.slice_voxels() * slices);
    buffer_.resize(count * sample_size(h.type));
    stream_->read(buffer_.data(), buffer_.size());
    const bool swap = (h.byte_order == ByteOrder::little) != host_is_little();
    decode(buffer_.data(), count, h.type, swap, h.value_scale, h.value_offset, out);
    if (h.type == SampleType::f32 || h.type == SampleType::f64) {
        const auto bad = std::find_if(out, out + count, [](float v) { return !std::isfinite(v); });
        if (bad != out + count) {
            const std::int64_t index = bad - out;
            const std::int64_t x = index % h.dims[0], y = (index / h.dims[0]) % h.dims[1];
            const std::int64_t z = next_slice_ + index / h.slice_voxels();
            throw FormatError(h.path.string(), "sample (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
                                                   std::to_string(z) + ")",
                              "a finite number", std::isnan(*bad) ? "NaN" : "infinity");
        }
    }
    next_slice_ += slices;
}

std::unique_ptr<VolumeReader> open_volume(const std::filesystem::path& path, const ReadOptions& options) {
    return std::make_unique<VolumeReader>(open_volume_source(path, options));
}

}  // namespace vdbmesh
