// OpenQVis .dat writer (the volume description of the OpenQVis renderer, Stegmaier et al.,
// openqvis.sourceforge.net/docu/fileformat.html): "Key: value" lines naming a raw file of
// UCHAR, USHORT or FLOAT samples. The format has no byte order key (readers assume
// little-endian), no value scale and no orientation or origin.

#include "vdbmesh/error.h"
#include "volume_writers.h"

namespace vdbmesh::detail {

namespace {

const char* format_name(SampleType type) {
    switch (type) {
        case SampleType::u8: return "UCHAR";
        case SampleType::u16: return "USHORT";
        default: return "FLOAT";
    }
}

}  // namespace

WriteResult write_openqvis(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices) {
    check_volume_header(path, header);
    require_type(path, header, "OpenQVis", {SampleType::u8, SampleType::u16, SampleType::f32});
    if (header.byte_order == ByteOrder::big && sample_size(header.type) > 1)
        throw Error(path.string() + ": OpenQVis has no byte order key and is read as little-endian; "
                                    "big-endian samples cannot be written");
    const Affine& m = header.index_to_world;
    if (!is_axis_aligned(m) || m[0][0] < 0 || m[1][1] < 0 || m[2][2] < 0 || m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0)
        throw Error(path.string() + ": OpenQVis stores only a spacing: no rotation, axis flip or origin");

    const std::filesystem::path data_path = sibling(path, ".raw");
    std::string text = "ObjectFileName: " + data_path.filename().string() + "\n";
    text += "TaggedFileName: ---\n";
    text += "Resolution: " + std::to_string(header.dims[0]) + " " + std::to_string(header.dims[1]) + " " +
            std::to_string(header.dims[2]) + "\n";
    text += "SliceThickness: " + format_number(header.spacing[0]) + " " + format_number(header.spacing[1]) + " " +
            format_number(header.spacing[2]) + "\n";
    text += std::string("Format: ") + format_name(header.type) + "\n";
    text += "NbrTags: 0\nObjectType: TEXTURE_VOLUME_OBJECT\nObjectModel: I\nGridType: EQUIDISTANT\n";
    if (!header.units.empty()) text += "Unit: " + header.units + "\n";

    write_detached(path, text, data_path, false, header, slices);
    return {{path, data_path}, false};
}

}  // namespace vdbmesh::detail
