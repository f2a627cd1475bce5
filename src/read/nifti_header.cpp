// The 348-byte header of Analyze 7.5 and NIfTI-1.
//
// Layout: Mayo Clinic, "ANALYZE 7.5 File Format" (struct dsr in dbh.h), and the NIfTI-1
// standard (nifti1.h, https://nifti.nimh.nih.gov/nifti-1). NIfTI-1 overlays Analyze, so one
// table of byte offsets serves both; magic "n+1" or "ni1" at byte 344 tells them apart.
// SPM's Analyze extensions: a value scale in funused1 (where NIfTI has scl_slope) and the
// origin in originator as three int16 (1-based voxel). Orientation follows nifti1.h's three
// methods: the sform rows when sform_code > 0, else the qform quaternion when qform_code > 0
// (qfac = pixdim[0] flips k), else plain pixdim scaling.

#include "nifti_header.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include "vdbmesh/parse_util.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

// Byte offsets of the fields read (Analyze name in parentheses when it differs).
constexpr std::size_t kSizeofHdr = 0;
constexpr std::size_t kDim = 40;        // int16[8]
constexpr std::size_t kVoxUnits = 56;   // Analyze only: char[4]
constexpr std::size_t kDatatype = 70;   // int16
constexpr std::size_t kBitpix = 72;     // int16
constexpr std::size_t kPixdim = 76;     // float[8]
constexpr std::size_t kVoxOffset = 108; // float
constexpr std::size_t kSclSlope = 112;  // float (funused1)
constexpr std::size_t kSclInter = 116;  // float
constexpr std::size_t kXyztUnits = 123; // uint8
constexpr std::size_t kQformCode = 252; // int16
constexpr std::size_t kOriginator = 253;  // Analyze (SPM) only: int16[3], unaligned
constexpr std::size_t kSformCode = 254;   // int16
constexpr std::size_t kQuatern = 256;     // float b, c, d
constexpr std::size_t kQoffset = 268;     // float x, y, z
constexpr std::size_t kSrow = 280;        // float[3][4]
constexpr std::size_t kMagic = 344;       // char[4]

constexpr std::size_t kSingleFileHeaderBytes = 352;  // 348 + the 4-byte extension flag
constexpr std::int32_t kNifti2HeaderBytes = 540;
constexpr std::uint64_t kMaxBytes = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());

struct TypeCode {
    std::int16_t code;
    SampleType type;
};
// NIfTI-1 DT_* codes; the Analyze ones (2, 4, 8, 16, 64) are the same. SPM2 also wrote the
// NIfTI-only integer codes into Analyze headers, so both formats accept all of them.
constexpr std::array<TypeCode, 8> kTypeCodes{{{2, SampleType::u8},
                                              {4, SampleType::i16},
                                              {8, SampleType::i32},
                                              {16, SampleType::f32},
                                              {64, SampleType::f64},
                                              {256, SampleType::i8},
                                              {512, SampleType::u16},
                                              {768, SampleType::u32}}};

std::string shown(double value) {
    std::ostringstream out;
    out.precision(9);
    out << value;
    return out.str();
}

/// Reads numbers in the header's byte order.
class Fields {
public:
    Fields(const unsigned char* bytes, ByteOrder order) : bytes_(bytes), order_(order) {}

    std::int16_t i16(std::size_t at) const { return get<std::int16_t>(at); }
    std::int32_t i32(std::size_t at) const { return get<std::int32_t>(at); }
    double f32(std::size_t at) const { return get<float>(at); }
    unsigned char u8(std::size_t at) const { return bytes_[at]; }
    std::string chars(std::size_t at, std::size_t count) const {
        const auto* begin = reinterpret_cast<const char*>(bytes_ + at);
        return std::string(begin, std::find(begin, begin + count, '\0'));
    }

private:
    template <typename T>
    T get(std::size_t at) const {
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, bytes_ + at, sizeof(T));
        const std::uint16_t probe = 1;
        const bool host_little = *reinterpret_cast<const unsigned char*>(&probe) == 1;
        if ((order_ == ByteOrder::little) != host_little) std::reverse(raw, raw + sizeof(T));
        T value;
        std::memcpy(&value, raw, sizeof(T));
        return value;
    }

    const unsigned char* bytes_;
    ByteOrder order_;
};

/// The byte order in which sizeof_hdr reads 348.
ByteOrder detect_byte_order(const unsigned char* bytes, const std::string& file) {
    const std::int32_t little = Fields(bytes, ByteOrder::little).i32(kSizeofHdr);
    const std::int32_t big = Fields(bytes, ByteOrder::big).i32(kSizeofHdr);
    if (little == static_cast<std::int32_t>(kNiftiHeaderBytes)) return ByteOrder::little;
    if (big == static_cast<std::int32_t>(kNiftiHeaderBytes)) return ByteOrder::big;
    const bool nifti2 = little == kNifti2HeaderBytes || big == kNifti2HeaderBytes;
    throw FormatError(file, "sizeof_hdr", "348 (Analyze 7.5 or NIfTI-1) in either byte order",
                      std::to_string(little) + (nifti2 ? " (NIfTI-2, not supported)" : ""));
}

/// dim[1..7], checked: dim[0] in 1..7, every used dim > 0, unused ones 1.
std::array<std::int64_t, 8> read_dims(const Fields& f, const std::string& file) {
    const int rank = f.i16(kDim);
    if (rank < 1 || rank > 7) throw FormatError(file, "dim[0]", "a rank in 1..7", std::to_string(rank));
    std::array<std::int64_t, 8> dims{};
    dims.fill(1);
    for (int i = 1; i <= rank; ++i) {
        dims[i] = f.i16(kDim + 2 * i);
        if (dims[i] <= 0) throw FormatError(file, "dim[" + std::to_string(i) + "]", "> 0", std::to_string(dims[i]));
    }
    dims[0] = rank;
    return dims;
}

SampleType read_type(const Fields& f, const std::string& file) {
    const std::int16_t code = f.i16(kDatatype);
    const auto known = std::find_if(kTypeCodes.begin(), kTypeCodes.end(), [&](const TypeCode& t) { return t.code == code; });
    if (known == kTypeCodes.end())
        throw FormatError(file, "datatype", "2 (u8), 4 (i16), 8 (i32), 16 (f32), 64 (f64), 256 (i8), 512 (u16) or 768 (u32)",
                          std::to_string(code) + " (unknown type)");
    const int bitpix = f.i16(kBitpix);
    const int expected = static_cast<int>(8 * sample_size(known->type));
    if (bitpix != expected)
        throw FormatError(file, "bitpix", std::to_string(expected) + " for datatype " + std::to_string(code),
                          std::to_string(bitpix));
    return known->type;
}

std::uint64_t read_vox_offset(const Fields& f, const std::string& file, bool single_file) {
    const double offset = f.f32(kVoxOffset);
    const double least = single_file ? static_cast<double>(kSingleFileHeaderBytes) : 0.0;
    if (!std::isfinite(offset) || offset < least || offset != std::floor(offset) || offset > 9.0e18)
        throw FormatError(file, "vox_offset",
                          "a whole number >= " + shown(least) + (single_file ? " (single-file NIfTI)" : ""), shown(offset));
    return static_cast<std::uint64_t>(offset);
}

/// pixdim[0..3], checked finite.
std::array<double, 4> read_pixdim(const Fields& f, const std::string& file) {
    std::array<double, 4> pixdim{};
    for (int i = 0; i < 4; ++i) {
        pixdim[i] = f.f32(kPixdim + 4 * i);
        if (!std::isfinite(pixdim[i]))
            throw FormatError(file, "pixdim[" + std::to_string(i) + "]", "a finite number", shown(pixdim[i]));
    }
    return pixdim;
}

/// |pixdim[1..3]| as voxel sizes; an axis beyond the rank may be 0 (taken as 1).
std::array<double, 3> voxel_sizes(const std::array<double, 4>& pixdim, int rank, const std::string& file) {
    std::array<double, 3> sizes{};
    for (int axis = 0; axis < 3; ++axis) {
        sizes[axis] = std::abs(pixdim[axis + 1]);
        if (sizes[axis] > 0) continue;
        if (axis + 1 > rank) sizes[axis] = 1;
        else throw FormatError(file, "pixdim[" + std::to_string(axis + 1) + "]", "a non-zero voxel size", "0");
    }
    return sizes;
}

/// The sform rows srow_x, srow_y, srow_z.
Affine sform_affine(const Fields& f, const std::string& file) {
    Affine m{};
    const char* kRowNames[3] = {"srow_x", "srow_y", "srow_z"};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) {
            m[r][c] = f.f32(kSrow + 16 * r + 4 * c);
            if (!std::isfinite(m[r][c]))
                throw FormatError(file, std::string(kRowNames[r]) + "[" + std::to_string(c) + "]", "a finite number",
                                  shown(m[r][c]));
        }
    return m;
}

/// nifti1.h method 2: rotation from the unit quaternion (a, b, c, d), a >= 0 implied, times
/// diag(dx, dy, qfac * dz), plus the qoffset translation.
Affine qform_affine(const Fields& f, const std::string& file, const std::array<double, 3>& sizes, double qfac) {
    const char* kNames[6] = {"quatern_b", "quatern_c", "quatern_d", "qoffset_x", "qoffset_y", "qoffset_z"};
    std::array<double, 6> q{};
    for (int i = 0; i < 6; ++i) {
        q[i] = f.f32(kQuatern + 4 * i);
        if (!std::isfinite(q[i])) throw FormatError(file, kNames[i], "a finite number", shown(q[i]));
    }
    double b = q[0], c = q[1], d = q[2];
    const double bcd = b * b + c * c + d * d;
    double a = 0;
    if (1.0 - bcd >= 1e-7) {
        a = std::sqrt(1.0 - bcd);
    } else {  // (b, c, d) is (nearly) unit length already: a 180-degree rotation, a = 0
        const double norm = std::sqrt(bcd);
        b /= norm, c /= norm, d /= norm;
    }
    const double rotation[3][3] = {{a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)},
                                   {2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b)},
                                   {2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b}};
    const double scale[3] = {sizes[0], sizes[1], qfac * sizes[2]};
    Affine m{};
    for (int r = 0; r < 3; ++r) {
        for (int col = 0; col < 3; ++col) m[r][col] = rotation[r][col] * scale[col];
        m[r][3] = q[3 + r];
    }
    return m;
}

/// SPM's Analyze origin: originator (1-based voxel) maps to world 0; all zero means index 0 does.
Affine analyze_affine(const Fields& f, const std::array<double, 3>& sizes) {
    std::array<double, 3> origin{};
    std::array<int, 3> originator{};
    for (int axis = 0; axis < 3; ++axis) originator[axis] = f.i16(kOriginator + 2 * axis);
    if (originator != std::array<int, 3>{0, 0, 0})
        for (int axis = 0; axis < 3; ++axis) origin[axis] = -sizes[axis] * (originator[axis] - 1);
    return axis_aligned_affine(sizes, origin);
}

/// Column norms of the affine (the spacing along i, j, k); throws when it is singular.
std::array<double, 3> spacing_of(const Affine& m, const std::string& file, const std::string& field) {
    std::array<double, 3> spacing{};
    for (int c = 0; c < 3; ++c) spacing[c] = std::sqrt(m[0][c] * m[0][c] + m[1][c] * m[1][c] + m[2][c] * m[2][c]);
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    // Relative to the column lengths, so that tiny voxels are not mistaken for a singular matrix.
    if (!(std::abs(det) > 1e-9 * spacing[0] * spacing[1] * spacing[2]))
        throw FormatError(file, field, "an invertible index-to-world matrix", "a singular one (determinant " + shown(det) + ")");
    return spacing;
}

std::string nifti_units(const Fields& f) {
    switch (f.u8(kXyztUnits) & 0x07) {
        case 1: return "m";
        case 2: return "mm";
        case 3: return "um";
        default: return "";
    }
}

std::string analyze_units(const Fields& f) {
    const std::string units = to_lower(trim(f.chars(kVoxUnits, 4)));
    if (units == "mm" || units == "m" || units == "um") return units;
    if (units == "micron") return "um";
    return "";
}

/// Sets the affine, spacing and units: sform, else qform, else pixdim (NIfTI); SPM origin (Analyze).
void read_geometry(const Fields& f, const std::string& file, bool nifti, int rank, VolumeHeader& h) {
    const std::array<double, 4> pixdim = read_pixdim(f, file);
    const int qform_code = f.i16(kQformCode), sform_code = f.i16(kSformCode);
    if (nifti && (qform_code < 0 || sform_code < 0))
        throw FormatError(file, qform_code < 0 ? "qform_code" : "sform_code", ">= 0",
                          std::to_string(std::min(qform_code, sform_code)));
    std::string field = "pixdim";
    if (nifti && sform_code > 0) {
        h.index_to_world = sform_affine(f, file);
        field = "srow_x/y/z";
    } else if (nifti && qform_code > 0) {
        const double qfac = pixdim[0] < 0 ? -1.0 : 1.0;
        h.index_to_world = qform_affine(f, file, voxel_sizes(pixdim, rank, file), qfac);
        field = "quatern_b/c/d";
    } else if (nifti) {
        h.index_to_world = axis_aligned_affine(voxel_sizes(pixdim, rank, file));
    } else {
        h.index_to_world = analyze_affine(f, voxel_sizes(pixdim, rank, file));
    }
    h.spacing = spacing_of(h.index_to_world, file, field);
    h.units = nifti ? nifti_units(f) : analyze_units(f);
}

/// scl_slope/scl_inter (NIfTI) or funused1 (SPM's Analyze scale); a zero or non-finite
/// slope means no scaling.
void read_scale(const Fields& f, bool nifti, VolumeHeader& h) {
    const double slope = f.f32(kSclSlope);
    if (slope == 0 || !std::isfinite(slope)) return;
    h.value_scale = slope;
    const double inter = nifti ? f.f32(kSclInter) : 0.0;
    h.value_offset = std::isfinite(inter) ? inter : 0.0;
}

}  // namespace

NiftiAnalyzeHeader parse_nifti_analyze_header(const unsigned char* bytes, std::size_t size,
                                              const std::filesystem::path& path) {
    const std::string file = path.string();
    if (size < kNiftiHeaderBytes)
        throw FormatError(file, "header", std::to_string(kNiftiHeaderBytes) + " bytes", std::to_string(size) + " bytes");
    const ByteOrder order = detect_byte_order(bytes, file);
    const Fields f(bytes, order);
    const std::string magic = f.chars(kMagic, 4);
    const bool nifti = magic == "n+1" || magic == "ni1";

    NiftiAnalyzeHeader result;
    result.single_file = magic == "n+1";
    VolumeHeader& h = result.header;
    h.format = nifti ? "nifti" : "analyze";
    h.path = path;
    h.byte_order = order;

    const std::array<std::int64_t, 8> dims = read_dims(f, file);
    const int rank = static_cast<int>(dims[0]);
    h.dims = {dims[1], dims[2], dims[3]};
    h.type = read_type(f, file);
    check_dims(path, "dim[1..3]", h.dims, sample_size(h.type));
    result.volume_bytes = static_cast<std::uint64_t>(h.voxel_count()) * sample_size(h.type);
    result.all_bytes = result.volume_bytes;
    for (int i = 4; i <= 7; ++i) {
        if (static_cast<std::uint64_t>(dims[i]) > kMaxBytes / result.all_bytes)
            throw FormatError(file, "dim", "a total byte size that fits in 63 bits", "dims up to dim[" + std::to_string(i) + "] overflow");
        result.all_bytes *= static_cast<std::uint64_t>(dims[i]);
    }
    if (result.all_bytes > result.volume_bytes)
        h.warnings.push_back(std::to_string(result.all_bytes / result.volume_bytes) +
                             " volumes (dim[4..7] > 1); only the first is read");

    result.vox_offset = read_vox_offset(f, file, result.single_file);
    read_geometry(f, file, nifti, rank, h);
    read_scale(f, nifti, h);
    return result;
}

}  // namespace vdbmesh::detail
