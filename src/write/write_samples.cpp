// The pieces every volume writer shares: a plain or gzip byte sink on zlib's gz* API (mode
// "wbT" writes plain bytes through the same calls), the float -> stored-sample encoder with the
// value scale, rounding, clamping and byte order, and the slice loop that streams a volume
// without holding it.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include "vdbmesh/parse_util.h"
#include "vdbmesh/atomic_file.h"
#include "vdbmesh/error.h"
#include "volume_writers.h"

namespace vdbmesh::detail {

namespace {

constexpr bool kHostLittle = __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__;

bool needs_swap(ByteOrder order) { return (order == ByteOrder::little) != kHostLittle; }

template <typename T>
void encode_as(const float* values, std::size_t count, double scale, double offset, bool swap, unsigned char* out) {
    for (std::size_t i = 0; i < count; ++i) {
        const double stored = (static_cast<double>(values[i]) - offset) / scale;
        T value;
        if constexpr (std::is_integral_v<T>) {
            const double lowest = static_cast<double>(std::numeric_limits<T>::lowest());
            const double highest = static_cast<double>(std::numeric_limits<T>::max());
            value = std::isnan(stored) ? T{0} : static_cast<T>(std::clamp(std::round(stored), lowest, highest));
        } else {
            value = static_cast<T>(stored);
        }
        unsigned char* bytes = out + i * sizeof(T);
        std::memcpy(bytes, &value, sizeof(T));
        if (swap) std::reverse(bytes, bytes + sizeof(T));
    }
}

}  // namespace

ByteSink::ByteSink(const std::filesystem::path& path, const std::filesystem::path& name, bool gzip, bool append)
    : name_(name), stream_name_(path.string()) {
    const std::string mode = std::string(append ? "ab" : "wb") + (gzip ? "6" : "T");
    file_ = gzopen(path.c_str(), mode.c_str());
    if (!file_) throw Error(name_.string() + ": cannot create the file (" + std::strerror(errno) + ")");
    gzbuffer(file_, 1 << 18);
}

ByteSink::~ByteSink() {
    if (file_) gzclose(file_);
}

void ByteSink::fail(const char* what) {
    int code = 0;
    const char* message = file_ ? gzerror(file_, &code) : "";
    throw Error(name_.string() + ": " + what + " (" +
                (code == Z_ERRNO ? std::string(std::strerror(errno)) : gzip_error_reason(message, stream_name_)) + ")");
}

void ByteSink::write(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    while (size > 0) {
        const unsigned chunk = static_cast<unsigned>(std::min<std::size_t>(size, 1u << 30));
        if (gzwrite(file_, bytes, chunk) != static_cast<int>(chunk)) fail("cannot write");
        bytes += chunk;
        size -= chunk;
    }
}

void ByteSink::close() {
    gzFile file = file_;
    file_ = nullptr;
    if (gzclose(file) != Z_OK) {
        throw Error(name_.string() + ": cannot finish writing (" + std::strerror(errno) + ")");
    }
}

void check_volume_header(const std::filesystem::path& path, const VolumeHeader& header) {
    check_dims(path, "dims", header.dims, sample_size(header.type));
    if (!std::isfinite(header.value_scale) || header.value_scale == 0)
        throw Error(path.string() + ": value scale: expected a finite non-zero number, got " +
                    format_number(header.value_scale));
    if (!std::isfinite(header.value_offset))
        throw Error(path.string() + ": value offset: expected a finite number, got " + format_number(header.value_offset));
    const auto from_affine = affine_spacing(header.index_to_world);
    for (int axis = 0; axis < 3; ++axis) {
        const double s = header.spacing[axis], a = from_affine[axis];
        if (!(s > 0) || !std::isfinite(s) || std::abs(s - a) > 1e-6 * std::max(s, a))
            throw Error(path.string() + ": spacing[" + std::to_string(axis) + "] is " + format_number(s) +
                        " but the affine's column " + std::to_string(axis) + " has length " + format_number(a) +
                        " (set index_to_world, e.g. axis_aligned_affine(spacing))");
    }
}

void require_type(const std::filesystem::path& path, const VolumeHeader& header, const std::string& format,
                  const std::vector<SampleType>& allowed) {
    if (std::find(allowed.begin(), allowed.end(), header.type) != allowed.end()) return;
    std::string names;
    for (SampleType type : allowed) names += (names.empty() ? "" : ", ") + to_string(type);
    throw Error(path.string() + ": " + format + " cannot store " + to_string(header.type) + " samples (it has " +
                names + ")");
}

void encode_samples(const VolumeHeader& header, const float* values, std::size_t count, unsigned char* out) {
    const bool swap = needs_swap(header.byte_order);
    const double scale = header.value_scale, offset = header.value_offset;
    visit_sample_type(header.type, [&](auto zero) { encode_as<decltype(zero)>(values, count, scale, offset, swap, out); });
}

void for_each_encoded_slice(const VolumeHeader& header, const SliceSource& slices,
                            const std::function<void(std::int64_t z, const std::vector<unsigned char>& bytes)>& write) {
    const auto count = static_cast<std::size_t>(header.slice_voxels());
    std::vector<float> slice(count);
    std::vector<unsigned char> bytes(count * sample_size(header.type));
    for (std::int64_t z = 0; z < header.dims[2]; ++z) {
        slices(z, slice.data());
        encode_samples(header, slice.data(), count, bytes.data());
        write(z, bytes);
    }
}

void write_samples(ByteSink& sink, const VolumeHeader& header, const SliceSource& slices) {
    for_each_encoded_slice(header, slices, [&](std::int64_t, const std::vector<unsigned char>& bytes) {
        sink.write(bytes.data(), bytes.size());
    });
}

void write_detached(const std::filesystem::path& header_path, const std::string& header_bytes,
                    const std::filesystem::path& data_path, bool gzip_data, const VolumeHeader& header,
                    const SliceSource& slices) {
    AtomicFile data(data_path);
    ByteSink data_sink(data.temp_path(), data_path, gzip_data);
    write_samples(data_sink, header, slices);
    data_sink.close();
    AtomicFile head(header_path);
    ByteSink head_sink(head.temp_path(), header_path, false);
    head_sink.write(header_bytes);
    head_sink.close();
    data.commit();
    head.commit();
}

void write_attached(const std::filesystem::path& path, const std::string& prefix, bool gzip,
                    const VolumeHeader& header, const SliceSource& slices) {
    AtomicFile file(path);
    ByteSink sink(file.temp_path(), path, gzip);
    sink.write(prefix);
    write_samples(sink, header, slices);
    sink.close();
    file.commit();
}

void BinaryRecord::put(std::size_t offset, const void* value, std::size_t size) {
    unsigned char* at = bytes_.data() + offset;
    std::memcpy(at, value, size);
    if (needs_swap(order_)) std::reverse(at, at + size);
}

void BinaryRecord::put_text(std::size_t offset, std::size_t capacity, const std::string& text) {
    std::memcpy(bytes_.data() + offset, text.data(), std::min(capacity, text.size()));
}

std::string format_number(double value) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

std::filesystem::path sibling(const std::filesystem::path& path, const std::string& extension) {
    std::filesystem::path result = path;
    return result.replace_extension(extension);
}

std::array<double, 3> affine_spacing(const Affine& affine) {
    std::array<double, 3> spacing{};
    for (int column = 0; column < 3; ++column)
        spacing[column] = std::sqrt(affine[0][column] * affine[0][column] + affine[1][column] * affine[1][column] +
                                    affine[2][column] * affine[2][column]);
    return spacing;
}

bool is_axis_aligned(const Affine& affine) {
    for (int row = 0; row < 3; ++row)
        for (int column = 0; column < 3; ++column)
            if (row != column && affine[row][column] != 0) return false;
    return true;
}

}  // namespace vdbmesh::detail
