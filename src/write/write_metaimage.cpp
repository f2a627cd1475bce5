// MetaImage writer (ITK MetaIO, https://itk.org/Wiki/ITK/MetaIO/Documentation): "Key = Value"
// lines ending with ElementDataFile, either LOCAL (.mha: the samples follow the header) or a
// .raw file beside the .mhd. TransformMatrix lists, as ITK writes it, the world direction of
// index axis 0, then of axis 1, then of axis 2; Offset is the world position of voxel (0,0,0).
// MetaImage has no value scale field.

#include "vdbmesh/error.h"
#include "volume_writers.h"

namespace vdbmesh::detail {

namespace {

const char* element_type(SampleType type) {
    switch (type) {
        case SampleType::u8: return "MET_UCHAR";
        case SampleType::i8: return "MET_CHAR";
        case SampleType::u16: return "MET_USHORT";
        case SampleType::i16: return "MET_SHORT";
        case SampleType::u32: return "MET_UINT";
        case SampleType::i32: return "MET_INT";
        case SampleType::f32: return "MET_FLOAT";
        case SampleType::f64: return "MET_DOUBLE";
    }
    return "";
}

std::string metaimage_header(const VolumeHeader& header, const std::string& data_file) {
    const Affine& m = header.index_to_world;
    std::string directions, origin, spacing, sizes;
    for (int axis = 0; axis < 3; ++axis) {
        for (int row = 0; row < 3; ++row)
            directions += (directions.empty() ? "" : " ") + format_number(m[row][axis] / header.spacing[axis]);
        const std::string space = axis == 0 ? "" : " ";
        origin += space + format_number(m[axis][3]);
        spacing += space + format_number(header.spacing[axis]);
        sizes += space + std::to_string(header.dims[axis]);
    }
    std::string text = "ObjectType = Image\nNDims = 3\nBinaryData = True\n";
    text += std::string("BinaryDataByteOrderMSB = ") + (header.byte_order == ByteOrder::big ? "True" : "False") + "\n";
    text += "CompressedData = False\n";
    text += "TransformMatrix = " + directions + "\n";
    text += "Offset = " + origin + "\n";
    text += "CenterOfRotation = 0 0 0\n";
    text += "ElementSpacing = " + spacing + "\n";
    text += "DimSize = " + sizes + "\n";
    text += std::string("ElementType = ") + element_type(header.type) + "\n";
    text += "ElementDataFile = " + data_file + "\n";
    return text;
}

}  // namespace

WriteResult write_metaimage(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices,
                            bool attached) {
    check_volume_header(path, header);
    if (attached) {
        write_attached(path, metaimage_header(header, "LOCAL"), false, header, slices);
        return {{path}, false};
    }
    const std::filesystem::path data_path = sibling(path, ".raw");
    write_detached(path, metaimage_header(header, data_path.filename().string()), data_path, false, header, slices);
    return {{path, data_path}, false};
}

}  // namespace vdbmesh::detail
