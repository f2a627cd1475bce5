// Analyze 7.5 writer (Mayo Clinic, "ANALYZE 7.5 File Format", the dsr struct: header_key,
// image_dimension, data_history; 348 bytes in a .hdr, samples in a .img), with the SPM
// conventions readers expect: the value scale in image_dimension.funused1 and the origin in
// data_history.originator as five int16, the 1-based voxel at world (0, 0, 0). Analyze has
// no rotation, no axis flip, no value offset and only the types u8, i16, i32, f32, f64.
// Also the fields NIfTI-1 keeps from this layout (analyze_common_fields, used by write_nifti.cpp).

#include <cmath>
#include <limits>

#include "vdbmesh/error.h"
#include "volume_writers.h"

namespace vdbmesh::detail {

namespace {

// Byte offsets in the 348-byte header (Analyze 7.5 names; NIfTI-1 shares the first group).
constexpr std::size_t kSizeofHdr = 0, kExtents = 32, kRegular = 38, kDim = 40, kVoxUnits = 56, kDatatype = 70,
                      kBitpix = 72, kPixdim = 76, kVoxOffset = 108, kFunused1 = 112, kDescrip = 148,
                      kOriginator = 253;

/// The datatype code of NIfTI-1 (nifti1.h DT_*), whose codes 2..64 are Analyze 7.5's.
std::int16_t datatype_code(SampleType type) {
    switch (type) {
        case SampleType::u8: return 2;
        case SampleType::i16: return 4;
        case SampleType::i32: return 8;
        case SampleType::f32: return 16;
        case SampleType::f64: return 64;
        case SampleType::i8: return 256;
        case SampleType::u16: return 512;
        case SampleType::u32: return 768;
    }
    return 0;
}

/// SPM's originator: per axis, the 1-based index of the voxel at world 0, which must be a
/// whole number since the field is an int16.
std::int16_t originator(const std::filesystem::path& path, const Affine& affine, int axis) {
    const double origin = 1 - affine[axis][3] / affine[axis][axis];
    const double whole = std::round(origin);
    if (std::abs(origin - whole) > 1e-6 || std::abs(whole) > std::numeric_limits<std::int16_t>::max())
        throw Error(path.string() + ": Analyze 7.5 stores the origin as a whole voxel index (originator); axis " +
                    std::to_string(axis) + " has its world origin at voxel " + format_number(origin - 1) +
                    " (write NIfTI instead)");
    return static_cast<std::int16_t>(whole);
}

void check_analyze_geometry(const std::filesystem::path& path, const VolumeHeader& header) {
    if (!is_axis_aligned(header.index_to_world))
        throw Error(path.string() + ": Analyze 7.5 cannot store a rotated or sheared orientation (write NIfTI instead)");
    for (int axis = 0; axis < 3; ++axis)
        if (header.index_to_world[axis][axis] < 0)
            throw Error(path.string() + ": Analyze 7.5 cannot store a flipped axis " + std::to_string(axis) +
                        " (write NIfTI instead)");
    if (header.value_offset != 0)
        throw Error(path.string() + ": Analyze 7.5 has no field for a value offset (got " +
                    format_number(header.value_offset) + "; write NIfTI instead)");
}

}  // namespace

BinaryRecord analyze_common_fields(const std::filesystem::path& path, const VolumeHeader& header) {
    BinaryRecord record(kAnalyzeHeaderSize, header.byte_order);
    record.put_i32(kSizeofHdr, static_cast<std::int32_t>(kAnalyzeHeaderSize));
    record.put_text(kRegular, 1, "r");
    record.put_i16(kDim, 3);
    for (int axis = 0; axis < 3; ++axis) {
        if (header.dims[axis] > std::numeric_limits<std::int16_t>::max())
            throw Error(path.string() + ": dim[" + std::to_string(axis + 1) + "] is " + std::to_string(header.dims[axis]) +
                        ", over the 32767 an Analyze/NIfTI-1 header can hold");
        record.put_i16(kDim + 2 * (axis + 1), static_cast<std::int16_t>(header.dims[axis]));
    }
    for (int unused = 4; unused < 8; ++unused) record.put_i16(kDim + 2 * unused, 1);
    record.put_i16(kDatatype, datatype_code(header.type));
    record.put_i16(kBitpix, static_cast<std::int16_t>(8 * sample_size(header.type)));
    for (int axis = 0; axis < 3; ++axis) record.put_f32(kPixdim + 4 * (axis + 1), static_cast<float>(header.spacing[axis]));
    record.put_text(kDescrip, 80, "written by vdbmesh");
    return record;
}

WriteResult write_analyze(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices) {
    check_volume_header(path, header);
    require_type(path, header, "Analyze 7.5",
                 {SampleType::u8, SampleType::i16, SampleType::i32, SampleType::f32, SampleType::f64});
    check_analyze_geometry(path, header);

    BinaryRecord record = analyze_common_fields(path, header);
    record.put_i32(kExtents, 16384);
    record.put_text(kVoxUnits, 4, header.units.empty() ? "mm" : header.units);
    record.put_f32(kVoxOffset, 0);
    record.put_f32(kFunused1, static_cast<float>(header.value_scale));
    for (int axis = 0; axis < 3; ++axis)
        record.put_i16(kOriginator + 2 * axis, originator(path, header.index_to_world, axis));

    const std::filesystem::path header_path = sibling(path, ".hdr"), data_path = sibling(path, ".img");
    write_detached(header_path, record.bytes(), data_path, false, header, slices);
    return {{header_path, data_path}, true};
}

}  // namespace vdbmesh::detail
