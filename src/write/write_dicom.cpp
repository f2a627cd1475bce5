// Writes a volume as a DICOM series, one CT Image Storage file per slice (DICOM PS3.3
// A.3 CT image IOD, C.7.6.2 image plane module, C.7.6.3 image pixel module, C.11.1 modality
// LUT; PS3.5 value representations: DS at most 16 characters, UI at most 64). GDCM encodes
// the files (Part 10 preamble and meta header, group lengths, value padding, byte order).
//
// UIDs are derived from the header under the 2.25 root, so the same phantom gives the same
// bytes on every run; two different phantoms get different UIDs.

#include "write_dicom.h"

#include <gdcmDataSet.h>
#include <gdcmFileMetaInformation.h>
#include <gdcmTrace.h>
#include <gdcmWriter.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <numeric>
#include <sstream>
#include <vector>

#include "vdbmesh/atomic_file.h"
#include "vdbmesh/error.h"
#include "vdbmesh/parse_util.h"
#include "volume_writers.h"

namespace vdbmesh::detail {

namespace {

using Vec3 = std::array<double, 3>;

constexpr const char* kCtImageStorage = "1.2.840.10008.5.1.4.1.1.2";

/// A DS value: the most precise decimal text that fits in 16 characters.
std::string decimal_string(double value) {
    char text[40];
    for (int digits = 16; digits > 1; --digits) {
        std::snprintf(text, sizeof text, "%.*g", digits, value);
        if (std::strlen(text) <= 16) break;
    }
    return text;
}

template <std::size_t N>
std::string decimal_strings(const std::array<double, N>& values) {
    return join_values(values, "\\", decimal_string);
}

/// A deterministic UID root: "2.25." and a 64-bit FNV-1a hash of the header's description.
std::string uid_root(const VolumeHeader& header) {
    std::string description = to_string(header.type);
    for (std::int64_t d : header.dims) description += " " + std::to_string(d);
    for (const auto& row : header.index_to_world)
        for (double v : row) description += " " + format_number(v);
    description += " " + format_number(header.value_scale) + " " + format_number(header.value_offset);
    std::uint64_t hash = 14695981039346656037ull;
    for (unsigned char c : description) hash = (hash ^ c) * 1099511628211ull;
    return "2.25." + std::to_string(hash);
}

/// The file name index of slice z: a fixed permutation when shuffling (z * k + 1 mod n, k coprime with n).
std::int64_t name_index(std::int64_t z, std::int64_t count, bool shuffle) {
    if (!shuffle || count < 2) return z;
    std::int64_t k = count / 2 + 1;
    while (std::gcd(k, count) != 1) ++k;
    return (z * k + 1) % count;
}

std::string slice_name(std::int64_t index, std::int64_t count) {
    const std::size_t width = std::max<std::size_t>(4, std::to_string(count).size());
    std::string digits = std::to_string(index);
    return "slice_" + std::string(width - std::min(width, digits.size()), '0') + digits + ".dcm";
}

/// The image plane of the affine: unit row and column directions, spacings, and the normal.
struct Plane {
    Vec3 row, column, origin, step;
    double row_spacing = 1, column_spacing = 1;  ///< along a column (between rows), along a row (between columns)
    double thickness = 1;                         ///< the step projected on the normal
};

Plane image_plane(const std::filesystem::path& folder, const Affine& affine) {
    Plane plane;
    Vec3 i_axis, j_axis;
    for (int r = 0; r < 3; ++r) {
        i_axis[r] = affine[r][0];
        j_axis[r] = affine[r][1];
        plane.step[r] = affine[r][2];
        plane.origin[r] = affine[r][3];
    }
    const auto length = [](const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
    plane.column_spacing = length(i_axis);
    plane.row_spacing = length(j_axis);
    const double cosine = (i_axis[0] * j_axis[0] + i_axis[1] * j_axis[1] + i_axis[2] * j_axis[2]) /
                          (plane.column_spacing * plane.row_spacing);
    if (!(std::abs(cosine) < 1e-6))
        throw Error(folder.string() + ": DICOM needs orthogonal row and column axes; the affine's first two columns have cosine " +
                    format_number(cosine));
    for (int r = 0; r < 3; ++r) {
        plane.row[r] = i_axis[r] / plane.column_spacing;
        plane.column[r] = j_axis[r] / plane.row_spacing;
    }
    const Vec3 normal{plane.row[1] * plane.column[2] - plane.row[2] * plane.column[1],
                      plane.row[2] * plane.column[0] - plane.row[0] * plane.column[2],
                      plane.row[0] * plane.column[1] - plane.row[1] * plane.column[0]};
    plane.thickness = std::abs(normal[0] * plane.step[0] + normal[1] * plane.step[1] + normal[2] * plane.step[2]);
    if (!(plane.thickness > 0)) throw Error(folder.string() + ": the affine's slice axis lies in the image plane");
    return plane;
}

/// Builds one file's data set, element by element.
class SliceDataSet {
public:
    void text(std::uint16_t group, std::uint16_t element, gdcm::VR vr, std::string value) {
        if (value.size() % 2) value += vr == gdcm::VR::UI ? '\0' : ' ';  // PS3.5 6.2: even lengths
        bytes(group, element, vr, value.data(), value.size());
    }
    void us(std::uint16_t group, std::uint16_t element, std::uint16_t value) {
        bytes(group, element, gdcm::VR::US, &value, sizeof value);  // host order; GDCM swaps for big endian
    }
    void bytes(std::uint16_t group, std::uint16_t element, gdcm::VR vr, const void* data, std::size_t size) {
        gdcm::DataElement element_value(gdcm::Tag(group, element));
        element_value.SetVR(vr);
        element_value.SetByteValue(static_cast<const char*>(data), static_cast<std::uint32_t>(size));
        data_set_.Replace(element_value);
    }
    const gdcm::DataSet& data_set() const { return data_set_; }

private:
    gdcm::DataSet data_set_;
};

/// The elements every slice shares (all but the instance and position).
SliceDataSet series_elements(const VolumeHeader& header, const Plane& plane, const std::string& root,
                             const std::string& series_uid) {
    const int bits = static_cast<int>(sample_size(header.type)) * 8;
    const bool is_signed = header.type == SampleType::i8 || header.type == SampleType::i16 || header.type == SampleType::i32;
    SliceDataSet d;
    d.text(0x0008, 0x0008, gdcm::VR::CS, "DERIVED\\SECONDARY\\AXIAL");
    d.text(0x0008, 0x0016, gdcm::VR::UI, kCtImageStorage);
    d.text(0x0008, 0x0060, gdcm::VR::CS, "CT");
    d.text(0x0008, 0x0070, gdcm::VR::LO, "vdbmesh");
    d.text(0x0008, 0x103e, gdcm::VR::LO, "vdbmesh phantom");
    d.text(0x0010, 0x0010, gdcm::VR::PN, "Phantom^vdbmesh");
    d.text(0x0010, 0x0020, gdcm::VR::LO, "PHANTOM");
    d.text(0x0018, 0x0050, gdcm::VR::DS, decimal_string(plane.thickness));
    d.text(0x0020, 0x000d, gdcm::VR::UI, root + ".1");
    d.text(0x0020, 0x000e, gdcm::VR::UI, series_uid);
    d.text(0x0020, 0x0011, gdcm::VR::IS, "1");
    d.text(0x0020, 0x0037, gdcm::VR::DS,
           decimal_strings(std::array{plane.row[0], plane.row[1], plane.row[2], plane.column[0], plane.column[1], plane.column[2]}));
    d.text(0x0020, 0x0052, gdcm::VR::UI, root + ".3");
    d.us(0x0028, 0x0002, 1);
    d.text(0x0028, 0x0004, gdcm::VR::CS, "MONOCHROME2");
    d.us(0x0028, 0x0010, static_cast<std::uint16_t>(header.dims[1]));
    d.us(0x0028, 0x0011, static_cast<std::uint16_t>(header.dims[0]));
    d.text(0x0028, 0x0030, gdcm::VR::DS, decimal_strings(std::array{plane.row_spacing, plane.column_spacing}));
    d.us(0x0028, 0x0100, static_cast<std::uint16_t>(bits));
    d.us(0x0028, 0x0101, static_cast<std::uint16_t>(bits));
    d.us(0x0028, 0x0102, static_cast<std::uint16_t>(bits - 1));
    d.us(0x0028, 0x0103, is_signed ? 1 : 0);
    d.text(0x0028, 0x1052, gdcm::VR::DS, decimal_string(header.value_offset));
    d.text(0x0028, 0x1053, gdcm::VR::DS, decimal_string(header.value_scale));
    return d;
}

void check_dicom_header(const std::filesystem::path& folder, const VolumeHeader& header) {
    check_volume_header(folder, header);
    require_type(folder, header, "DICOM", {SampleType::u8, SampleType::i8, SampleType::u16, SampleType::i16,
                                           SampleType::u32, SampleType::i32});
    for (int axis = 0; axis < 2; ++axis)
        if (header.dims[axis] > 65535)
            throw Error(folder.string() + ": DICOM Rows and Columns are at most 65535; dims[" + std::to_string(axis) +
                        "] is " + std::to_string(header.dims[axis]));
}

/// A folder beside the target, removed with its content unless released.
class TemporaryFolder {
public:
    explicit TemporaryFolder(std::filesystem::path path) : path_(std::move(path)) {
        std::error_code ec;
        if (!std::filesystem::create_directory(path_, ec))
            throw Error(path_.string() + ": cannot create the temporary folder (" + ec.message() + ")");
    }
    ~TemporaryFolder() {
        std::error_code ignored;
        if (!released_) std::filesystem::remove_all(path_, ignored);
    }
    TemporaryFolder(const TemporaryFolder&) = delete;
    TemporaryFolder& operator=(const TemporaryFolder&) = delete;
    void release() { released_ = true; }

private:
    std::filesystem::path path_;
    bool released_ = false;
};

/// GDCM's writer with its option to write the data set alone (no preamble, no meta header) made public.
class SliceWriter : public gdcm::Writer {
public:
    using gdcm::Writer::SetWriteDataSetOnly;
};

/// GDCM writes into memory (it asserts when its stream fails, as on a full disk), then the
/// bytes go to @a path through a stream we check. Errors name @a shown (the slice in the target folder).
void write_file(const std::filesystem::path& path, const std::filesystem::path& shown, gdcm::Writer& writer) {
    std::ostringstream bytes;
    writer.SetStream(bytes);
    if (!writer.Write()) throw Error(shown.string() + ": GDCM cannot encode the slice");
    std::ofstream out(path, std::ios::binary);
    if (!out) throw Error(shown.string() + ": cannot create the file (" + std::strerror(errno) + ")");
    out << bytes.str();
    out.close();
    if (!out) throw Error(shown.string() + ": cannot write the file (" + std::strerror(errno) + ")");
}

/// Turns off GDCM's messages on stderr (the library never prints). Idempotent.
void silence_gdcm_messages() {
    static std::once_flag once;
    std::call_once(once, [] {
        gdcm::Trace::SetDebug(false);
        gdcm::Trace::SetWarning(false);
        gdcm::Trace::SetError(false);
    });
}

}  // namespace

WriteResult write_dicom_series(const std::filesystem::path& folder, const VolumeHeader& header, const SliceSource& slices,
                               const DicomWriteOptions& options) {
    const std::filesystem::path target = folder.has_filename() ? folder : folder.parent_path();
    check_dicom_header(target, header);
    std::error_code ec;
    if (std::filesystem::exists(target, ec) &&
        !(std::filesystem::is_directory(target, ec) && std::filesystem::is_empty(target, ec)))
        throw Error(target.string() + ": a DICOM series needs a new or empty folder; this one exists and is not empty");
    silence_gdcm_messages();

    const Plane plane = image_plane(target, header.index_to_world);
    const std::string root = uid_root(header);
    const std::string series_uid = options.series_uid.empty() ? root + ".2" : options.series_uid;
    SliceDataSet data_set = series_elements(header, plane, root, series_uid);

    AtomicFile atomic(target);
    TemporaryFolder temporary(atomic.temp_path());
    VolumeHeader host_order = header;  // GDCM swaps the OW/OB values itself for big endian
    host_order.byte_order = __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__ ? ByteOrder::little : ByteOrder::big;
    for_each_encoded_slice(host_order, slices, [&](std::int64_t z, const std::vector<unsigned char>& samples) {
        Vec3 position;
        for (int r = 0; r < 3; ++r) position[r] = plane.origin[r] + static_cast<double>(z) * plane.step[r];
        data_set.text(0x0008, 0x0018, gdcm::VR::UI, root + ".4." + std::to_string(z + 1));
        data_set.text(0x0020, 0x0013, gdcm::VR::IS, std::to_string(z + 1));
        data_set.text(0x0020, 0x0032, gdcm::VR::DS, decimal_strings(position));
        data_set.bytes(0x7fe0, 0x0010, sample_size(header.type) == 1 ? gdcm::VR::OB : gdcm::VR::OW, samples.data(),
                       samples.size());

        SliceWriter writer;
        writer.GetFile().SetDataSet(data_set.data_set());
        if (options.bare) {
            writer.GetFile().GetHeader().SetDataSetTransferSyntax(gdcm::TransferSyntax::ImplicitVRLittleEndian);
            writer.SetWriteDataSetOnly(true);
        } else {
            writer.GetFile().GetHeader().SetDataSetTransferSyntax(header.byte_order == ByteOrder::big
                                                                      ? gdcm::TransferSyntax::ExplicitVRBigEndian
                                                                      : gdcm::TransferSyntax::ExplicitVRLittleEndian);
        }
        const std::string name = slice_name(name_index(z, header.dims[2], options.shuffle_names), header.dims[2]);
        write_file(atomic.temp_path() / name, target / name, writer);
    });
    atomic.commit();
    temporary.release();
    return WriteResult{{target}, true};
}

}  // namespace vdbmesh::detail
