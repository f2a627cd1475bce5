// NIfTI-1 writer (NIfTI Data Format Working Group, nifti1.h, 2004): the 348-byte header,
// then in a .nii (magic "n+1") 4 zero extension bytes and the samples from vox_offset 352, or
// in a pair (magic "ni1") a .hdr and the samples in a .img. .nii.gz is the same stream gzipped.
//
// The orientation is written twice from index_to_world: the sform (srow_x/y/z) as the affine
// itself, and the qform as the nearest rotation (polar decomposition of the direction
// cosines), qfac = -1 when the axes are left-handed, pixdim[1..3] the column lengths and
// qoffset the translation. Both codes are 1 (NIFTI_XFORM_SCANNER_ANAT). The value scale is
// scl_slope / scl_inter.

#include <array>
#include <cmath>

#include "vdbmesh/error.h"
#include "volume_writers.h"

namespace vdbmesh::detail {

namespace {

// Byte offsets of the NIfTI-1 fields written here beyond the Analyze ones (nifti1.h).
constexpr std::size_t kPixdim = 76, kVoxOffset = 108, kSclSlope = 112, kSclInter = 116, kXyztUnits = 123,
                      kQformCode = 252, kSformCode = 254, kQuatern = 256, kQoffset = 268, kSrow = 280, kMagic = 344;
constexpr std::int16_t kScannerAnat = 1;
constexpr std::size_t kSingleFileOffset = kAnalyzeHeaderSize + 4;  // the header plus the extension flag bytes

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<Vec3, 3>;  // [column][row]: columns are the index axes' directions

Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// The rotation nearest to @a m (det > 0): iterate m <- (m + m^-T) / 2, whose columns
/// (c1 x c2, c2 x c0, c0 x c1) / det are those of m^-T (Higham's polar iteration).
Mat3 nearest_rotation(Mat3 m) {
    for (int iteration = 0; iteration < 100; ++iteration) {
        const double det = dot(m[0], cross(m[1], m[2]));
        const Mat3 dual{cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1])};
        double change = 0;
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) {
                const double next = 0.5 * (m[c][r] + dual[c][r] / det);
                change = std::max(change, std::abs(next - m[c][r]));
                m[c][r] = next;
            }
        if (change < 1e-15) break;
    }
    return m;
}

/// Quaternion (b, c, d) with a >= 0 of the rotation @a m (Shepperd's method); R(row, column)
/// = m[column][row] in nifti1.h's convention.
Vec3 quaternion_bcd(const Mat3& m) {
    auto R = [&](int row, int column) { return m[column][row]; };
    const double trace = R(0, 0) + R(1, 1) + R(2, 2);
    double a, b, c, d;
    if (trace > 0) {
        const double s = 2 * std::sqrt(1 + trace);  // 4a
        a = s / 4, b = (R(2, 1) - R(1, 2)) / s, c = (R(0, 2) - R(2, 0)) / s, d = (R(1, 0) - R(0, 1)) / s;
    } else if (R(0, 0) >= R(1, 1) && R(0, 0) >= R(2, 2)) {
        const double s = 2 * std::sqrt(1 + R(0, 0) - R(1, 1) - R(2, 2));  // 4b
        a = (R(2, 1) - R(1, 2)) / s, b = s / 4, c = (R(0, 1) + R(1, 0)) / s, d = (R(0, 2) + R(2, 0)) / s;
    } else if (R(1, 1) >= R(2, 2)) {
        const double s = 2 * std::sqrt(1 + R(1, 1) - R(0, 0) - R(2, 2));  // 4c
        a = (R(0, 2) - R(2, 0)) / s, b = (R(0, 1) + R(1, 0)) / s, c = s / 4, d = (R(1, 2) + R(2, 1)) / s;
    } else {
        const double s = 2 * std::sqrt(1 + R(2, 2) - R(0, 0) - R(1, 1));  // 4d
        a = (R(1, 0) - R(0, 1)) / s, b = (R(0, 2) + R(2, 0)) / s, c = (R(1, 2) + R(2, 1)) / s, d = s / 4;
    }
    if (a < 0) b = -b, c = -c, d = -d;  // NIfTI stores only b, c, d and takes a = sqrt(1 - b^2 - c^2 - d^2)
    return {b, c, d};
}

void put_qform(BinaryRecord& record, const std::filesystem::path& path, const Affine& affine) {
    Mat3 axes{};
    for (int c = 0; c < 3; ++c) {
        const double length = std::sqrt(affine[0][c] * affine[0][c] + affine[1][c] * affine[1][c] + affine[2][c] * affine[2][c]);
        for (int r = 0; r < 3; ++r) axes[c][r] = affine[r][c] / length;
    }
    const double handedness = dot(axes[0], cross(axes[1], axes[2]));
    if (!(std::abs(handedness) > 1e-6))
        throw Error(path.string() + ": the affine's axes are (nearly) coplanar; no orientation can be written");
    const double qfac = handedness < 0 ? -1.0 : 1.0;
    for (double& v : axes[2]) v *= qfac;
    const Vec3 bcd = quaternion_bcd(nearest_rotation(axes));
    record.put_f32(kPixdim, static_cast<float>(qfac));
    for (int i = 0; i < 3; ++i) {
        record.put_f32(kQuatern + 4 * i, static_cast<float>(bcd[i]));
        record.put_f32(kQoffset + 4 * i, static_cast<float>(affine[i][3]));
    }
    record.put_i16(kQformCode, kScannerAnat);
}

void put_sform(BinaryRecord& record, const Affine& affine) {
    for (int row = 0; row < 3; ++row)
        for (int column = 0; column < 4; ++column)
            record.put_f32(kSrow + 16 * row + 4 * column, static_cast<float>(affine[row][column]));
    record.put_i16(kSformCode, kScannerAnat);
}

/// nifti1.h's xyzt_units code of a spatial unit (0: unknown).
char units_code(const std::string& units) {
    if (units == "m") return 1;
    if (units == "mm") return 2;
    if (units == "um") return 3;
    return 0;
}

std::string nifti_header(const std::filesystem::path& path, const VolumeHeader& header, bool single_file) {
    BinaryRecord record = analyze_common_fields(path, header);
    record.put_f32(kVoxOffset, single_file ? static_cast<float>(kSingleFileOffset) : 0.0f);
    record.put_f32(kSclSlope, static_cast<float>(header.value_scale));
    record.put_f32(kSclInter, static_cast<float>(header.value_offset));
    record.put_text(kXyztUnits, 1, std::string(1, units_code(header.units)));
    put_qform(record, path, header.index_to_world);
    put_sform(record, header.index_to_world);
    record.put_text(kMagic, 4, single_file ? std::string("n+1", 4) : std::string("ni1", 4));
    std::string bytes = record.bytes();
    if (single_file) bytes.append(kSingleFileOffset - kAnalyzeHeaderSize, '\0');  // no extensions
    return bytes;
}

}  // namespace

WriteResult write_nifti(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices,
                        bool single_file, bool gzip) {
    check_volume_header(path, header);
    if (single_file) {
        write_attached(path, nifti_header(path, header, true), gzip, header, slices);
        return {{path}, true};
    }
    const std::filesystem::path header_path = sibling(path, ".hdr"), data_path = sibling(path, ".img");
    write_detached(header_path, nifti_header(header_path, header, false), data_path, gzip, header, slices);
    return {{header_path, data_path}, true};
}

}  // namespace vdbmesh::detail
